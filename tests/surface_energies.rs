//! Kaji's stitching energies (issue 27: "finite differences check each energy's
//! gradient"): `E_T`'s and `E_S`'s gradients against central differences; the rigid blend
//! is where `E_T` is stationary (the factorised cotangent system is the energy's); the
//! shape iterations lower `E_S`; the energies' errors. The deformer's energy is checked in
//! tests/surface_deform.rs.

#[path = "common/poses3.rs"]
mod poses3;

use std::f64::consts::PI;

use bunraku::surface3::{Stitch, StitchEnergy, SurfaceBlender, SurfaceOptions, Tetrisation};
use bunraku::Error;
use poses3::{bend, cylinder, diagonal, twist};

/// A capped cylinder with a uv seam, and a blender of it bent 90° and twisted 270°.
fn blender(options: SurfaceOptions) -> SurfaceBlender {
    let (rest, tris) = cylinder(0.25, 3.0, 12, 16, true);
    let mut b = SurfaceBlender::register(rest.clone(), tris, options).unwrap();
    b.add_pose(&bend(&rest, 3.0, 0.5 * PI)).unwrap();
    b.add_pose(&twist(&rest, |z| 1.5 * PI * z / 3.0)).unwrap();
    b
}

/// The blend of `weights`, one position per welded vertex.
fn welded_blend(b: &mut SurfaceBlender, weights: &[f64]) -> Vec<[f64; 3]> {
    let out = b.blend(weights).unwrap();
    b.surface().representatives().iter().map(|&r| out[r as usize]).collect()
}

fn gradient(b: &SurfaceBlender, e: StitchEnergy, w: &[f64], x: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let mut g = vec![[0.0; 3]; x.len()];
    b.energy_gradient(e, w, x, &mut g).unwrap();
    g
}

fn largest(g: &[[f64; 3]]) -> f64 {
    g.iter().flatten().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn each_energy_gradient_matches_finite_differences() {
    let mut b = blender(SurfaceOptions::default());
    let diag = diagonal(b.surface().vertices());
    for weights in [[0.3, 0.5], [1.4, -0.3]] {
        // Away from any minimum: the blend, wiggled by 2 % of the diagonal.
        let x: Vec<[f64; 3]> = welded_blend(&mut b, &weights)
            .iter()
            .enumerate()
            .map(|(i, p)| [0, 1, 2].map(|k| p[k] + 0.02 * diag * ((3 * i + k) as f64 * 1.7).sin()))
            .collect();
        for energy in [StitchEnergy::Rigid, StitchEnergy::Shape] {
            let g = gradient(&b, energy, &weights, &x);
            let scale = largest(&g);
            assert!(scale > 0.0);
            let h = 1e-6 * diag;
            for i in (0..x.len()).step_by(5) {
                for k in 0..3 {
                    let (mut plus, mut minus) = (x.clone(), x.clone());
                    plus[i][k] += h;
                    minus[i][k] -= h;
                    let fd = (b.energy(energy, &weights, &plus).unwrap()
                        - b.energy(energy, &weights, &minus).unwrap())
                        / (2.0 * h);
                    assert!(
                        (fd - g[i][k]).abs() <= 1e-6 * scale,
                        "{energy:?} {weights:?} vertex {i}.{k}: {fd} against {}",
                        g[i][k]
                    );
                }
            }
        }
    }
}

#[test]
fn the_rigid_blend_is_where_e_t_is_stationary() {
    for options in [SurfaceOptions::default(), SurfaceOptions { anchor: Some(40), ..Default::default() }] {
        let mut b = blender(options);
        let diag = diagonal(b.surface().vertices());
        for weights in [[0.0, 0.0], [0.3, 0.5], [1.0, 0.0], [1.4, -0.3]] {
            let x = welded_blend(&mut b, &weights);
            // The gradient's scale: at the linear blend of the rest and the poses.
            let rest = b.surface().vertices().to_vec();
            let (bent, twisted) = (bend(&rest, 3.0, 0.5 * PI), twist(&rest, |z| 1.5 * PI * z / 3.0));
            let linear: Vec<[f64; 3]> = (0..rest.len())
                .map(|i| {
                    let w0 = 1.0 - weights[0] - weights[1];
                    [0, 1, 2].map(|k| w0 * rest[i][k] + weights[0] * bent[i][k] + weights[1] * twisted[i][k])
                })
                .collect();
            let scale = largest(&gradient(&b, StitchEnergy::Rigid, &[0.3, 0.5], &linear)).max(1.0);
            let g = largest(&gradient(&b, StitchEnergy::Rigid, &weights, &x));
            assert!(g <= 1e-10 * scale, "{options:?} {weights:?}: |∇E_T| {g:e} against {scale:e}");
            // And a minimum: any move raises it.
            let e = b.energy(StitchEnergy::Rigid, &weights, &x).unwrap();
            for s in 0..4 {
                let moved: Vec<[f64; 3]> = x
                    .iter()
                    .enumerate()
                    .map(|(i, p)| [0, 1, 2].map(|k| p[k] + 1e-3 * diag * ((i * 7 + k * 3 + s) as f64).cos()))
                    .collect();
                assert!(b.energy(StitchEnergy::Rigid, &weights, &moved).unwrap() > e);
            }
        }
    }
}

#[test]
fn shape_iterations_lower_e_s() {
    let weights = [0.0, 0.5];
    let mut energies = Vec::new();
    let mut gradients = Vec::new();
    for iterations in [0, 1, 3, 10] {
        let mut b = blender(SurfaceOptions { stitch: Stitch::Shape { iterations }, ..Default::default() });
        let x = welded_blend(&mut b, &weights);
        energies.push(b.energy(StitchEnergy::Shape, &weights, &x).unwrap());
        gradients.push(largest(&gradient(&b, StitchEnergy::Shape, &weights, &x)));
    }
    // Measured on this cylinder: E_S 0.0212, 0.0180, 0.0178, 0.0178 and |∇E_S| 0.025,
    // 0.0047, 0.0009, 0.0006: the iterations approach a point where E_S is (nearly)
    // stationary, though they solve E_T for the targets R(Â) S(C), not E_S itself.
    assert!(energies.windows(2).all(|w| w[1] < w[0]), "E_S {energies:?}");
    assert!(energies[3] < 0.9 * energies[0], "E_S {energies:?}");
    assert!(gradients.windows(2).all(|w| w[1] < w[0]), "|∇E_S| {gradients:?}");
    assert!(gradients[3] < 0.1 * gradients[0], "|∇E_S| {gradients:?}");
}

#[test]
fn the_energies_check_their_input() {
    let b = blender(SurfaceOptions::default());
    let x = b.surface().vertices().to_vec();
    let mut g = vec![[0.0; 3]; x.len()];
    let e = StitchEnergy::Rigid;
    assert!(matches!(b.energy(e, &[0.5], &x), Err(Error::CountMismatch { what: "weights", .. })));
    assert!(matches!(b.energy(e, &[0.5, f64::NAN], &x), Err(Error::BadWeight { index: 1, .. })));
    assert!(matches!(b.energy(e, &[0.5, 0.0], &x[1..]), Err(Error::CountMismatch { what: "positions", .. })));
    let mut bad = x.clone();
    bad[3][1] = f64::INFINITY;
    assert!(matches!(b.energy(e, &[0.5, 0.0], &bad), Err(Error::NonFinite { .. })));
    assert!(matches!(
        b.energy_gradient(e, &[0.5, 0.0], &x, &mut g[1..]),
        Err(Error::CountMismatch { what: "gradient", .. })
    ));
    let (rest, tris) = cylinder(0.25, 3.0, 12, 4, false);
    let edge = SurfaceOptions { tetrisation: Tetrisation::Edge, ..Default::default() };
    let b = SurfaceBlender::register(rest.clone(), tris, edge).unwrap();
    assert!(matches!(b.energy(e, &[], &rest), Err(Error::BadOption { name: "tetrisation", .. })));
}
