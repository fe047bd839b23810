//! The three methods through the public API (issue "Deformation that never tears"): what
//! each guarantees exactly, the nonlinear method's relations to the two-step one, the area
//! constraint, the regularisation's invariances, the injective method's guarantee, budget,
//! lag, reset and warm start, and bad options.

mod common;
#[path = "common/surfaces.rs"]
mod surfaces;

use bunraku::deform::{Method, TermWeights};
use bunraku::quality::quality_2d;
use bunraku::{Error, Handle, Mesh, Options, Pin, Rest};
use common::{assert_bits_eq, max_dist, rigid, Grid};

fn disc(rings: u32) -> Mesh {
    let (v, t) = surfaces::disc(rings);
    Mesh::new(v, t).unwrap()
}

fn area(mesh: &Mesh, p: &[[f64; 2]]) -> f64 {
    mesh.triangles()
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|k| p[k as usize]);
            0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
        })
        .sum()
}

/// Updates with the same targets until the injective method converges.
fn settle(pinned: &mut bunraku::Pinned, targets: &[[f64; 2]]) -> Vec<[f64; 2]> {
    for _ in 0..500 {
        pinned.update(targets).unwrap();
        if pinned.report().converged {
            return pinned.positions().to_vec();
        }
    }
    panic!("not converged after 500 updates: {:?}", pinned.report());
}

#[test]
fn every_method_returns_a_rigid_motion_of_all_pins() {
    let mesh = Grid::new(8, 6).jitter(0.2, 4).mesh();
    let handles = [Handle::Point([0.5, 0.5]), Handle::Point([7.5, 0.6]), Handle::Point([4.0, 5.5])];
    let points = [[0.5, 0.5], [7.5, 0.6], [4.0, 5.5]];
    let methods = [
        Options::two_step(),
        Options { regularization: 2.0, ..Options::two_step() },
        Options { method: Method::Nonlinear, ..Options::default() },
        Options { method: Method::Nonlinear, preserve_area: true, iterations: 7, ..Options::default() },
        Options { method: Method::Nonlinear, regularization: 0.5, ..Options::default() },
        Options { budget_ms: 100.0, ..Options::default() },
    ];
    for options in methods {
        for (angle, shift) in [(0.0, [0.0, 0.0]), (2.3, [1000.0, -500.0]), (-0.4, [3.0, 2.0])] {
            let m = rigid(angle, shift);
            let rest = Rest::register(mesh.clone(), options).unwrap();
            let mut pinned = rest.compile(&handles).unwrap();
            let targets: Vec<[f64; 2]> = points.iter().map(|&p| m(p)).collect();
            let out = if options.method == Method::Injective {
                settle(&mut pinned, &targets)
            } else {
                pinned.update(&targets).unwrap().to_vec()
            };
            let want: Vec<[f64; 2]> = mesh.vertices().iter().map(|&p| m(p)).collect();
            let tolerance = if options.method == Method::Injective { 1e-7 } else { 1e-8 };
            let d = max_dist(&out, &want);
            assert!(
                d <= tolerance * mesh.diameter(),
                "{:?} λ {}: {d}",
                options.method,
                options.regularization
            );
        }
    }
}

#[test]
fn nonlinear_with_no_iterations_is_the_two_step_method() {
    let mesh = disc(10);
    let handles = [Handle::Point([-0.5, 0.1]), Handle::Point([0.6, 0.0])];
    let targets = [[-0.5, 0.1], [1.4, 0.7]];
    for regularization in [0.0, 1.5] {
        let two = Options { regularization, ..Options::two_step() };
        let none = Options { method: Method::Nonlinear, iterations: 0, regularization, ..Options::default() };
        let a = Rest::register(mesh.clone(), two)
            .unwrap()
            .compile(&handles)
            .unwrap()
            .update(&targets)
            .unwrap()
            .to_vec();
        let mut p = Rest::register(mesh.clone(), none).unwrap().compile(&handles).unwrap();
        assert_bits_eq(p.update(&targets).unwrap(), &a, "0 iterations");
        // And iterations do change it, towards a less distorted shape.
        let more = Options { iterations: 10, ..none };
        let b = Rest::register(mesh.clone(), more)
            .unwrap()
            .compile(&handles)
            .unwrap()
            .update(&targets)
            .unwrap()
            .to_vec();
        assert!(max_dist(&a, &b) > 1e-3);
        if regularization == 0.0 {
            // Weng's energy is not the isometric error, but on this drag it lowers its worst.
            let (qa, qb) = (quality_2d(&mesh, &a).unwrap(), quality_2d(&mesh, &b).unwrap());
            assert!(qb.isometric.max < qa.isometric.max, "{} vs {}", qb.isometric.max, qa.isometric.max);
        }
    }
}

#[test]
fn the_area_constraint_holds_the_area() {
    let mesh = disc(9);
    let rest_area = area(&mesh, mesh.vertices());
    let handles = [Handle::Point([-0.7, 0.0]), Handle::Point([0.7, 0.0])];
    for iterations in [1, 3, 12] {
        let options =
            Options { method: Method::Nonlinear, preserve_area: true, iterations, ..Options::default() };
        let mut p = Rest::register(mesh.clone(), options).unwrap().compile(&handles).unwrap();
        for target in [[1.5, 0.0], [0.3, 0.2], [2.2, -1.0]] {
            let out = p.update(&[[-0.7, 0.0], target]).unwrap().to_vec();
            let r = area(&mesh, &out) / rest_area - 1.0;
            assert!(
                r.abs() <= 1e-9,
                "{iterations} iterations, target {target:?}: relative area change {r:e}"
            );
        }
        // Without the constraint, the same stretch changes the area.
        let free = Options { preserve_area: false, ..options };
        let out = Rest::register(mesh.clone(), free)
            .unwrap()
            .compile(&handles)
            .unwrap()
            .update(&[[-0.7, 0.0], [1.5, 0.0]])
            .unwrap()
            .to_vec();
        assert!((area(&mesh, &out) / rest_area - 1.0).abs() > 1e-3);
    }
}

/// The regularisation is dimensionless: scaling the shape and the targets scales the result,
/// for every λ; λ = 0 is the paper's method bit for bit; λ > 0 changes the result and, on a
/// far drag, lowers the worst distortion and the number of folds.
#[test]
fn regularization_is_scale_free_and_smooths() {
    let base = surfaces::disc(16);
    let handles = |s: f64| [Handle::Point([-0.5 * s, 0.0]), Handle::Point([0.5 * s, 0.0])];
    let targets = |s: f64| [[-0.5 * s, 0.0], [1.3 * s, 0.9 * s]];
    let run = |s: f64, lambda: f64| {
        let v: Vec<[f64; 2]> = base.0.iter().map(|p| [p[0] * s, p[1] * s]).collect();
        let mesh = Mesh::new(v, base.1.clone()).unwrap();
        let options = Options { regularization: lambda, ..Options::two_step() };
        let out = Rest::register(mesh.clone(), options)
            .unwrap()
            .compile(&handles(s))
            .unwrap()
            .update(&targets(s))
            .unwrap()
            .to_vec();
        (mesh, out)
    };
    let (mesh, plain) = run(1.0, 0.0);
    let q0 = quality_2d(&mesh, &plain).unwrap();
    for lambda in [0.5, 5.0] {
        let (_, one) = run(1.0, lambda);
        let (_, big) = run(250.0, lambda);
        let scaled: Vec<[f64; 2]> = big.iter().map(|p| [p[0] / 250.0, p[1] / 250.0]).collect();
        assert!(max_dist(&one, &scaled) < 1e-9, "λ = {lambda}: not scale-free ({})", max_dist(&one, &scaled));
        assert!(max_dist(&one, &plain) > 1e-3, "λ = {lambda} changes nothing");
    }
    let (_, smooth) = run(1.0, 10.0);
    let q = quality_2d(&mesh, &smooth).unwrap();
    assert!(q0.flipped > 0, "the test drag must fold the paper's method");
    assert!(
        q.flipped < q0.flipped && q.isometric.max < q0.isometric.max,
        "{} / {} flips, {} / {}",
        q.flipped,
        q0.flipped,
        q.isometric.max,
        q0.isometric.max
    );
}

/// The injective method: no triangle with a non-positive area and no winding defect after
/// any update of a drag that folds the two-step method, with a small work cap (counted,
/// not timed, so that the test does the same work in a debug build and on a loaded
/// machine); the pin catches up once the drag is held; reset returns to rest; a pin added
/// mid-pose where the material is moves nothing.
#[test]
fn injective_never_folds_and_catches_up() {
    let mesh = disc(12);
    let handles = [Handle::Point([-0.5, 0.0]), Handle::Point([0.5, 0.0])];
    let options = Options { max_solves: Some(16), ..Options::default() };
    let rest = Rest::register(mesh.clone(), options).unwrap();
    let mut p = rest.compile(&handles).unwrap();
    let end = [1.7, 0.9];
    let frames = 40;
    for f in 1..=frames + 40 {
        let s = f.min(frames) as f64 / frames as f64;
        let out = p.update(&[[-0.5, 0.0], [0.5 + s * (end[0] - 0.5), s * end[1]]]).unwrap().to_vec();
        let q = quality_2d(&mesh, &out).unwrap();
        assert_eq!((q.flipped, q.winding_defects), (0, 0), "frame {f}");
        assert!(q.triangles.iter().all(|t| t.area_ratio > 0.0));
    }
    assert!(p.report().lag < 0.01 * mesh.diameter(), "{:?}", p.report());
    let two = Rest::register(mesh.clone(), Options::two_step())
        .unwrap()
        .compile(&handles)
        .unwrap()
        .update(&[[-0.5, 0.0], end])
        .unwrap()
        .to_vec();
    assert!(quality_2d(&mesh, &two).unwrap().flipped > 0, "the drag must fold the two-step method");

    // A third pin where vertex 0 (the centre) is now.
    let posed = settle(&mut p, &[[-0.5, 0.0], end]);
    let centre = posed[0];
    let mut pins: Vec<Pin> = handles.iter().copied().map(Pin::from).collect();
    pins.push(Pin::from(Handle::Vertex(0)));
    let mut q = rest.compile_pins_from(&pins, &posed).unwrap();
    let after = q.update(&[[-0.5, 0.0], end, centre]).unwrap().to_vec();
    assert!(max_dist(&after, &posed) < 1e-4, "jumped by {}", max_dist(&after, &posed));
    q.reset();
    assert_bits_eq(q.positions(), mesh.vertices(), "reset");
}

/// An update stops once its budget is spent, overshooting it by at most its longest step
/// (the report's own clock; how long an update takes is measured by the benchmarks, not
/// asserted here).
#[test]
fn injective_respects_its_budget() {
    let mesh = disc(40); // about 5000 vertices
    for budget in [1.0, 3.0, 10.0] {
        let rest = Rest::register(mesh.clone(), Options { budget_ms: budget, ..Options::default() }).unwrap();
        let mut p = rest.compile(&[Handle::Point([-0.5, 0.0]), Handle::Point([0.5, 0.0])]).unwrap();
        // A target held far away: every update has work left. The first (the targets moved)
        // makes one Newton iteration; the held ones iterate until the budget is spent.
        for k in 0..6 {
            p.update(&[[-0.5, 0.0], [2.5, 1.5]]).unwrap();
            let r = p.report();
            assert!(k == 0 || r.elapsed_ms > budget, "the drag must need more than the budget: {r:?}");
            assert!(r.elapsed_ms <= budget + r.longest_step_ms + 1e-9, "{budget} ms: {r:?}");
        }
    }
}

/// A counted budget (`max_solves`) does the same work whatever the clock: two puppets give
/// the same bits, and no update makes more back-substitutions than asked (plus the one
/// that starts each Newton iteration; at least 10 when the targets moved).
#[test]
fn injective_counted_budget_is_reproducible() {
    let mesh = disc(16);
    let run = || {
        let options = Options { max_solves: Some(7), budget_ms: 1e-6, ..Options::default() };
        let rest = Rest::register(mesh.clone(), options).unwrap();
        let mut p = rest.compile(&[Handle::Point([-0.5, 0.0]), Handle::Point([0.5, 0.0])]).unwrap();
        let mut reports = Vec::new();
        for f in 1..=12 {
            let s = f.min(6) as f64 / 6.0;
            p.update(&[[-0.5, 0.0], [0.5 + 1.5 * s, 1.2 * s]]).unwrap();
            reports.push(p.report());
        }
        (p.positions().to_vec(), reports)
    };
    let (a, ra) = run();
    let (b, rb) = run();
    assert_bits_eq(&a, &b, "counted budget");
    for (f, (x, y)) in (1..).zip(ra.iter().zip(&rb)) {
        assert_eq!((x.iterations, x.solves, x.converged), (y.iterations, y.solves, y.converged));
        // Every update works (a held one may only continue conjugate gradients that the
        // budget stopped, with no Newton step finished) or has converged.
        assert!(x.iterations >= 1 || x.converged || x.solves > 0, "{x:?}");
        // An update whose targets moved (the first 6) makes at least 10 conjugate-gradient
        // steps before it looks at its budget (the injective method's MOVED_CG); a held one
        // may also start an iteration that the budget stops (its conjugate gradients go on
        // in the next update; `iterations` counts only finished ones).
        let asked = if f <= 6 { 10 + x.iterations } else { 7 + x.iterations + 1 };
        assert!(x.solves <= asked, "update {f}: {x:?}");
    }
}

#[test]
fn bad_options_are_named() {
    let mesh = disc(3);
    let bad = [
        ("budget_ms", Options { budget_ms: 0.0, ..Options::default() }),
        ("budget_ms", Options { budget_ms: f64::NAN, ..Options::default() }),
        ("max_solves", Options { max_solves: Some(0), ..Options::default() }),
        ("regularization", Options { regularization: -1.0, ..Options::two_step() }),
        ("regularization", Options { regularization: f64::INFINITY, ..Options::two_step() }),
        ("regularization", Options { regularization: 1.0, ..Options::default() }),
        ("iterations", Options { method: Method::Nonlinear, iterations: 5000, ..Options::default() }),
        (
            "mean_value",
            Options {
                term_weights: TermWeights { mean_value: -1.0, ..TermWeights::default() },
                ..Options::default()
            },
        ),
        (
            "edge_length",
            Options {
                term_weights: TermWeights { mean_value: 0.0, edge_length: 0.0, laplacian: 1.0 },
                ..Options::default()
            },
        ),
    ];
    for (name, options) in bad {
        match Rest::register(mesh.clone(), options) {
            Err(Error::BadOption { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{name}: {other:?}"),
        }
    }
}
