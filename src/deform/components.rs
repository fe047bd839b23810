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
    /// A component with one pin (its index), which holds a position: translated with it.
    Translate(usize),
    /// A component whose pins hold only rotations: turned and scaled about the first (its
    /// index), whose point stays.
    Spin(usize),
}

/// Writes the positions of the vertices that are not solved: `rest` for a component
/// without pins, `rest + target − pin point` for a component with one position pin,
/// `pin point + τ (rest − pin point)` for one turned by a rotation pin's `τ`. Solved
/// vertices keep what `positions` holds.
pub(crate) fn place_unsolved(
    motion: &[Motion],
    rest: &[[f64; 2]],
    pin_points: &[[f64; 2]],
    targets: &[[f64; 2]],
    rotations: &[super::pins::Rotation],
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
            Motion::Spin(h) => {
                let q = pin_points[h];
                let tau = rotations[h].complex();
                let d = num_complex::Complex64::new(r[0] - q[0], r[1] - q[1]) * tau;
                *p = [q[0] + d.re, q[1] + d.im];
            }
        }
    }
}
