//! Regularised harmonic surface deformation (issue 27, `bunraku::surface3::SurfaceDeformer`)
//! and `surface_quality`: rest in, rest out; rigid motions of every handle reproduced for
//! any β; the regulariser's cut of the one-vertex-handle spike; scale invariance; the
//! energy's gradient against finite differences; stationarity of the solution; welded seams;
//! no allocation in an update (a counting global allocator); every error.

#[path = "common/bars.rs"]
mod bars;
#[path = "common/counting.rs"]
mod counting;

use bars::{apply, bar, turn_about, Raw3};
use bunraku::surface3::{
    surface_quality, DeformOperator, DeformOptions, SurfaceDeformer, DEFAULT_REGULARIZATION,
};
use bunraku::Error;
use counting::allocations;
use std::f64::consts::FRAC_PI_2;

#[global_allocator]
static GLOBAL: counting::Counting = counting::Counting;

const IDENTITY: [f64; 16] = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0];

/// The test bar: 0.4 × 0.4 × 2 along z, squares of 0.1.
fn test_bar() -> Raw3 {
    bar([0.4, 0.4, 2.0], [4, 4, 20])
}

fn options(beta: f64, operator: DeformOperator) -> DeformOptions {
    DeformOptions { regularization: beta, operator }
}

fn every_option() -> Vec<DeformOptions> {
    let mut out = Vec::new();
    for beta in [0.0, 0.05, 0.2, DEFAULT_REGULARIZATION, 0.9] {
        for op in [DeformOperator::Plain, DeformOperator::Aligned] {
            out.push(options(beta, op));
        }
    }
    out
}

/// Caller vertices with `z` within `eps` of `at`.
fn slab(v: &[[f64; 3]], at: f64, eps: f64) -> Vec<u32> {
    (0..v.len() as u32).filter(|&i| (v[i as usize][2] - at).abs() <= eps).collect()
}

fn max_distance(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt())
        .fold(0.0, f64::max)
}

fn deform(raw: &Raw3, opts: DeformOptions, fixed: &[u32], handles: &[&[u32]], m: &[f64]) -> Vec<[f64; 3]> {
    let mut d = SurfaceDeformer::register(raw.0.clone(), raw.1.clone(), opts).unwrap();
    d.compile(fixed, handles).unwrap();
    let mut out = vec![[0.0; 3]; raw.0.len()];
    d.update_into(m, &mut out).unwrap();
    out
}

#[test]
fn rest_in_rest_out() {
    let raw = test_bar();
    let (bottom, top) = (slab(&raw.0, 0.0, 1e-9), slab(&raw.0, 2.0, 1e-9));
    for opts in every_option() {
        let out = deform(&raw, opts, &bottom, &[&top], &IDENTITY);
        assert!(max_distance(&out, &raw.0) < 1e-12, "{opts:?}: {}", max_distance(&out, &raw.0));
    }
}

#[test]
fn a_rigid_motion_of_every_handle_is_reproduced_for_any_beta() {
    let raw = test_bar();
    let (bottom, top) = (slab(&raw.0, 0.0, 1e-9), slab(&raw.0, 2.0, 1e-9));
    let m = turn_about([0.6, 0.0, 0.8], 2.0, [0.2, 0.2, 1.0], [0.3, -1.0, 0.5]);
    let both = [m, m].concat();
    for opts in every_option() {
        let out = deform(&raw, opts, &[], &[&bottom, &top], &both);
        let expected: Vec<[f64; 3]> = raw.0.iter().map(|&p| apply(&m, p)).collect();
        let error = max_distance(&out, &expected);
        assert!(error < 1e-9, "{opts:?}: {error}");
    }
}

/// The largest per-triangle isometric error of a one-vertex handle on the bar's top corner,
/// turned 90° about x and lifted, with the bottom slab fixed.
fn one_vertex_spike(beta: f64, op: DeformOperator, scale: f64) -> (f64, Vec<[f64; 3]>) {
    let raw = test_bar();
    let v: Vec<[f64; 3]> = raw.0.iter().map(|p| p.map(|x| x * scale)).collect();
    let bottom = slab(&v, 0.0, 1e-9);
    let tip = v.iter().position(|p| p == &[0.4 * scale, 0.4 * scale, 2.0 * scale]).unwrap() as u32;
    let m = turn_about([1.0, 0.0, 0.0], FRAC_PI_2, v[tip as usize], [0.0, 0.0, 0.1 * scale]);
    let out = deform(&(v.clone(), raw.1.clone()), options(beta, op), &bottom, &[&[tip]], &m);
    let q = surface_quality(v, &out, raw.1).unwrap();
    (q.isometric.max, out)
}

#[test]
fn the_regulariser_cuts_the_spike_of_a_one_vertex_handle_at_least_fourfold() {
    for op in [DeformOperator::Plain, DeformOperator::Aligned] {
        let (plain, _) = one_vertex_spike(0.0, op, 1.0);
        let (smooth, _) = one_vertex_spike(DEFAULT_REGULARIZATION, op, 1.0);
        eprintln!("{op:?}: max isometric error {plain:.4} at β = 0, {smooth:.4} at the default");
        assert!(plain >= 4.0 * smooth, "{op:?}: {plain} against {smooth}");
    }
}

#[test]
fn a_mesh_scaled_100_times_deforms_alike() {
    for op in [DeformOperator::Plain, DeformOperator::Aligned] {
        for beta in [0.0, DEFAULT_REGULARIZATION] {
            let (e1, small) = one_vertex_spike(beta, op, 1.0);
            let (e100, large) = one_vertex_spike(beta, op, 100.0);
            let scaled: Vec<[f64; 3]> = small.iter().map(|p| p.map(|x| x * 100.0)).collect();
            assert!(max_distance(&scaled, &large) < 1e-8 * 200.0, "{op:?} {beta}");
            assert!((e1 - e100).abs() < 1e-9, "{op:?} {beta}: {e1} against {e100}");
        }
    }
}

#[test]
fn the_energy_gradient_matches_finite_differences() {
    let raw = bar([0.4, 0.4, 1.0], [2, 2, 5]);
    let (bottom, top) = (slab(&raw.0, 0.0, 1e-9), slab(&raw.0, 1.0, 1e-9));
    let m = turn_about([0.0, 1.0, 0.0], 0.7, [0.2, 0.2, 1.0], [0.1, 0.0, 0.0]);
    for opts in every_option() {
        let mut d = SurfaceDeformer::register(raw.0.clone(), raw.1.clone(), opts).unwrap();
        d.compile(&bottom, &[&top]).unwrap();
        let mut out = vec![[0.0; 3]; raw.0.len()];
        d.update_into(&m, &mut out).unwrap();
        // A point away from the minimum: the welded rest, wiggled.
        let rest = d.surface().vertices().to_vec();
        let x: Vec<[f64; 3]> = rest
            .iter()
            .enumerate()
            .map(|(i, p)| [0, 1, 2].map(|k| p[k] + 0.05 * ((3 * i + k) as f64).sin()))
            .collect();
        let mut g = vec![[0.0; 3]; x.len()];
        d.energy_gradient(&x, &mut g);
        let h = 1e-6;
        for i in (0..x.len()).step_by(7) {
            for k in 0..3 {
                let (mut plus, mut minus) = (x.clone(), x.clone());
                plus[i][k] += h;
                minus[i][k] -= h;
                let fd = (d.energy(&plus) - d.energy(&minus)) / (2.0 * h);
                assert!(
                    (fd - g[i][k]).abs() < 1e-6 * (1.0 + fd.abs()),
                    "{opts:?} vertex {i}.{k}: {fd} against {}",
                    g[i][k]
                );
            }
        }
    }
}

#[test]
fn the_solution_is_a_minimum_over_the_free_vertices() {
    let raw = bar([0.4, 0.4, 1.0], [2, 2, 6]);
    let (bottom, top) = (slab(&raw.0, 0.0, 1e-9), slab(&raw.0, 1.0, 1e-9));
    let m = turn_about([0.0, 1.0, 0.0], 1.2, [0.2, 0.2, 1.0], [0.0, 0.2, 0.0]);
    for opts in every_option() {
        let mut d = SurfaceDeformer::register(raw.0.clone(), raw.1.clone(), opts).unwrap();
        d.compile(&bottom, &[&top]).unwrap();
        let mut out = vec![[0.0; 3]; raw.0.len()];
        d.update_into(&m, &mut out).unwrap();
        let welded: Vec<[f64; 3]> = d.surface().representatives().iter().map(|&r| out[r as usize]).collect();
        let mut g = vec![[0.0; 3]; welded.len()];
        d.energy_gradient(&welded, &mut g);
        let weld = d.surface().weld_map();
        let constrained: Vec<usize> = bottom.iter().chain(&top).map(|&v| weld[v as usize] as usize).collect();
        let scale = d.energy(&welded).max(1e-3);
        for (v, gv) in g.iter().enumerate().filter(|(v, _)| !constrained.contains(v)) {
            assert!(gv.iter().all(|x| x.abs() < 1e-9 * scale.max(1.0)), "{opts:?} vertex {v}: {gv:?}");
        }
    }
}

#[test]
fn welded_seams_stay_closed_and_updates_allocate_nothing() {
    let raw = test_bar();
    assert_eq!(raw.0.len(), 470, "the bar's faces repeat their edges");
    let (bottom, top) = (slab(&raw.0, 0.0, 1e-9), slab(&raw.0, 2.0, 1e-9));
    let mut d = SurfaceDeformer::register(raw.0.clone(), raw.1.clone(), DeformOptions::default()).unwrap();
    assert!(d.surface().vertices().len() < raw.0.len());
    d.compile(&bottom, &[&top]).unwrap();
    let mut out = vec![[0.0; 3]; raw.0.len()];
    let mut flat = vec![0.0f32; 3 * raw.0.len()];
    let mut count = 0;
    for step in 0..5 {
        let m = turn_about([0.0, 1.0, 0.0], 0.3 * step as f64, [0.2, 0.2, 2.0], [0.0; 3]);
        count += allocations(|| d.update_into(&m, &mut out).unwrap()).0;
        count += allocations(|| d.update_into_f32(&m, &mut flat).unwrap()).0;
        for (i, p) in raw.0.iter().enumerate() {
            for (j, q) in raw.0.iter().enumerate().skip(i + 1) {
                if p == q {
                    assert_eq!(out[i], out[j], "seam {i}/{j} opened");
                }
            }
        }
    }
    assert_eq!(count, 0);
}

#[test]
fn bad_input_is_refused_and_leaves_the_deformer_as_it_was() {
    let raw = test_bar();
    let (bottom, top) = (slab(&raw.0, 0.0, 1e-9), slab(&raw.0, 2.0, 1e-9));
    let bad = SurfaceDeformer::register(raw.0.clone(), raw.1.clone(), options(1.0, DeformOperator::Plain));
    assert!(matches!(bad, Err(Error::BadOption { name: "regularization", .. })));
    let mut d = SurfaceDeformer::register(raw.0.clone(), raw.1.clone(), DeformOptions::default()).unwrap();
    d.compile(&bottom, &[&top]).unwrap();
    let m = turn_about([0.0, 1.0, 0.0], 0.5, [0.2, 0.2, 2.0], [0.0; 3]);
    let mut before = vec![[0.0; 3]; raw.0.len()];
    d.update_into(&m, &mut before).unwrap();
    let n = raw.0.len() as u32;
    match d.compile(&bottom, &[&[n]]) {
        Err(Error::BadRegion { region, index: 0, vertex, .. }) => {
            assert_eq!((region.as_str(), vertex), ("handles[0]", n))
        }
        other => panic!("{other:?}"),
    }
    let middle = slab(&raw.0, 1.0, 1e-9)[0];
    match d.compile(&bottom, &[&top, &[middle, bottom[3]]]) {
        Err(Error::BadRegion { region, index: 1, .. }) => assert_eq!(region, "handles[1]"),
        other => panic!("{other:?}"),
    }
    assert!(matches!(d.compile(&bottom, &[]), Err(Error::BadOption { name: "handles", .. })));
    let mut nan = m;
    nan[5] = f64::NAN;
    assert!(matches!(d.update_into(&nan, &mut before.clone()), Err(Error::NonFinite { flat: 5, .. })));
    let mut mirror = IDENTITY;
    mirror[0] = -1.0;
    assert!(matches!(d.update_into(&mirror, &mut before.clone()), Err(Error::BadHandle { handle: 0, .. })));
    let mut projective = IDENTITY;
    projective[3] = 0.5;
    assert!(matches!(
        d.update_into(&projective, &mut before.clone()),
        Err(Error::BadHandle { handle: 0, .. })
    ));
    assert!(matches!(d.update_into(&[m, m].concat(), &mut before.clone()), Err(Error::CountMismatch { .. })));
    assert!(matches!(d.update_into(&m, &mut before[1..].to_vec()), Err(Error::CountMismatch { .. })));
    // The handle set and the pose are as they were.
    let mut after = vec![[0.0; 3]; raw.0.len()];
    d.update_into(&m, &mut after).unwrap();
    assert_eq!(before, after);
}

#[test]
fn a_piece_no_region_reaches_stays_at_rest() {
    let raw = test_bar();
    let mut v = raw.0.clone();
    let mut t = raw.1.clone();
    let shift = v.len() as u32;
    v.extend(raw.0.iter().map(|p| [p[0] + 3.0, p[1], p[2]]));
    t.extend(raw.1.iter().map(|tri| tri.map(|i| i + shift)));
    let (bottom, top) = (slab(&raw.0, 0.0, 1e-9), slab(&raw.0, 2.0, 1e-9));
    let m = turn_about([0.0, 1.0, 0.0], 0.8, [0.2, 0.2, 2.0], [0.0; 3]);
    let out = deform(&(v.clone(), t), DeformOptions::default(), &bottom, &[&top], &m);
    assert!(max_distance(&out[shift as usize..], &v[shift as usize..]) < 1e-12);
    assert!(max_distance(&out[..shift as usize], &raw.0) > 0.1);
}

#[test]
fn surface_quality_measures_rigid_motions_scales_and_volume() {
    let raw = test_bar();
    let m = turn_about([0.0, 0.6, 0.8], 1.0, [0.0; 3], [1.0, 2.0, 3.0]);
    let moved: Vec<[f64; 3]> = raw.0.iter().map(|&p| apply(&m, p)).collect();
    let q = surface_quality(raw.0.clone(), &moved, raw.1.clone()).unwrap();
    assert!(q.isometric.max < 1e-20 && q.conformal.max < 1e-20 && q.edge_strain.max < 1e-12);
    assert!(q.volume_change.unwrap().abs() < 1e-12);
    let doubled: Vec<[f64; 3]> = raw.0.iter().map(|p| p.map(|x| 2.0 * x)).collect();
    let q = surface_quality(raw.0.clone(), &doubled, raw.1.clone()).unwrap();
    assert!((q.isometric.max - 2.0).abs() < 1e-12 && q.conformal.max < 1e-20);
    assert!((q.area_ratio.mean - 4.0).abs() < 1e-12 && (q.edge_strain.max - 1.0).abs() < 1e-12);
    assert!((q.volume_change.unwrap() - 7.0).abs() < 1e-12);
    // An open plate has no volume; a stretch along x gives σ = (2, 1) as in 2D.
    let plate: Vec<[f64; 3]> = (0..9).map(|i| [(i % 3) as f64 * 0.5, (i / 3) as f64 * 0.5, 1.0]).collect();
    let top: Vec<[u32; 3]> =
        [0u32, 1, 3, 4].iter().flat_map(|&a| [[a, a + 1, a + 4], [a, a + 4, a + 3]]).collect();
    let stretched: Vec<[f64; 3]> = plate.iter().map(|p| [2.0 * p[0], p[1], p[2]]).collect();
    let q = surface_quality(plate, &stretched, top).unwrap();
    assert_eq!(q.volume_change, None);
    assert!(q.triangles.iter().all(|t| (t.sigma[0] - 2.0).abs() < 1e-12 && (t.sigma[1] - 1.0).abs() < 1e-12));
    assert!(matches!(
        surface_quality(raw.0.clone(), &moved[1..], raw.1.clone()),
        Err(Error::CountMismatch { .. })
    ));
}
