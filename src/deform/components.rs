//! How each connected component of the mesh moves ([conventions](crate::conventions) 8):
//! a component with two or more pins is solved; one with a single pin is translated with
//! it; one with none stays at rest. (The paper, section 6, asks for "more than two
//! handles"; two distinct pins already make both systems non-singular on a connected
//! component, and fewer leave it free to slide, so the solve is replaced by the motion the
//! least-squares energy has as its limit.)

/// How a component moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Motion {
    /// A component with two or more pins: solved.
    Solve,
    /// A component with no pin: stays at rest.
    Rest,
    /// A component with one pin (its index): translated with it.
    Translate(usize),
}

/// The motion of every vertex, from the component of each vertex and the component each
/// pin lies in.
pub(crate) fn vertex_motion(
    component_of: &[u32],
    component_count: usize,
    pin_components: &[u32],
) -> Vec<Motion> {
    let mut per_component = vec![Vec::new(); component_count];
    for (k, &c) in pin_components.iter().enumerate() {
        per_component[c as usize].push(k);
    }
    let motion: Vec<Motion> = per_component
        .iter()
        .map(|pins| match pins.len() {
            0 => Motion::Rest,
            1 => Motion::Translate(pins[0]),
            _ => Motion::Solve,
        })
        .collect();
    component_of.iter().map(|&c| motion[c as usize]).collect()
}

/// Writes the positions of the vertices that are not solved: `rest` for a component
/// without pins, `rest + target − pin point` for a component with one pin. Solved vertices
/// keep what `positions` holds.
pub(crate) fn place_unsolved(
    motion: &[Motion],
    rest: &[[f64; 2]],
    pin_points: &[[f64; 2]],
    targets: &[[f64; 2]],
    positions: &mut [[f64; 2]],
) {
    for ((p, m), r) in positions.iter_mut().zip(motion).zip(rest) {
        match *m {
            Motion::Solve => {}
            Motion::Rest => *p = *r,
            Motion::Translate(h) => {
                let (t, q) = (targets[h], pin_points[h]);
                *p = [r[0] + t[0] - q[0], r[1] + t[1] - q[1]];
            }
        }
    }
}
