//! Property tests: random polygons through `mesh_outline` and random alpha masks through
//! `mesh_image` never panic and give either a valid, registrable mesh or a clear error
//! (256 cases each); the injective method never folds a random shape under random drags
//! (1000 cases). `PROPTEST_CASES=n` runs n of each; a few seconds each in debug builds.
#![cfg(not(target_arch = "wasm32"))]

use bunraku::meshing::{mesh_image, mesh_outline, ImageOptions, OutlineOptions};
use bunraku::{Error, Handle, Options, Rest};
use proptest::prelude::*;

fn valid_or_clear(result: Result<bunraku::Mesh, Error>) -> Result<(), TestCaseError> {
    match result {
        Ok(mesh) => {
            prop_assert!(!mesh.triangles().is_empty());
            Rest::register(mesh, Options::two_step())
                .map_err(|e| TestCaseError::fail(format!("register: {e}")))?;
        }
        Err(e) => prop_assert!(!e.to_string().is_empty()),
    }
    Ok(())
}

proptest! {
    // 256 cases each; PROPTEST_CASES=n runs n.
    #![proptest_config(ProptestConfig {
        cases: std::env::var("PROPTEST_CASES").ok().and_then(|n| n.parse().ok()).unwrap_or(256),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Arbitrary point lists (mostly self-intersecting): a mesh or an error, never a panic.
    #[test]
    fn random_polygons(points in prop::collection::vec((-10.0f64..10.0, -10.0f64..10.0), 0..12),
                       spacing in 0.3f64..5.0) {
        let outer: Vec<[f64; 2]> = points.iter().map(|&(x, y)| [x, y]).collect();
        valid_or_clear(mesh_outline(&outer, &[], &OutlineOptions::new().with_spacing(spacing)))?;
    }

    /// Star-shaped polygons (sorted angles, random radii) are simple: they always mesh.
    #[test]
    fn random_star_shaped_polygons(polar in prop::collection::vec((0.0f64..0.9, 0.2f64..3.0), 5..40),
                                   with_hole in any::<bool>()) {
        // Angle k in [k, k + 0.9) / n: increasing, gaps below half a turn, so the origin is
        // inside and the polygon is simple.
        let n = polar.len() as f64;
        let outer: Vec<[f64; 2]> = polar
            .iter()
            .enumerate()
            .map(|(k, &(jitter, r))| {
                let a = (k as f64 + jitter) / n * std::f64::consts::TAU;
                [r * a.cos(), r * a.sin()]
            })
            .collect();
        // A small square hole around the origin fits inside any such star (radius ≥ 0.2).
        let holes = if with_hole { vec![vec![[-0.05, -0.05], [0.05, -0.05], [0.05, 0.05], [-0.05, 0.05]]] } else { vec![] };
        let result = mesh_outline(&outer, &holes, &OutlineOptions::new().with_max_vertices(3000));
        if let Err(e) = &result {
            return Err(TestCaseError::fail(format!("star-shaped polygon rejected: {e}")));
        }
        valid_or_clear(result)?;
    }

    /// Random alpha masks with random options: a mesh that stays on the picture and
    /// registers, or `NoOpaquePixel`.
    #[test]
    fn random_alpha_masks(w in 1u32..40, h in 1u32..40, density in 0.0f64..1.0, seed in any::<u64>(),
                          margin in 0.0f64..4.0, simplify in 0.0f64..3.0, min_area in 0.0f64..20.0,
                          threshold in 1u8..=255) {
        let mut state = seed | 1;
        let mut rgba = vec![0u8; (w * h * 4) as usize];
        for p in rgba.chunks_exact_mut(4) {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let r = (state >> 11) as f64 / (1u64 << 53) as f64;
            p[3] = if r < density { (state & 0xff) as u8 | 0x80 } else { (state & 0x7f) as u8 };
        }
        let o = ImageOptions { margin, simplify, min_area, alpha_threshold: threshold, ..ImageOptions::default() };
        match mesh_image(&rgba, w, h, &o) {
            Ok(shape) => {
                // On the picture, up to rounding in mesh_outline's normalised frame.
                let eps = 1e-9 * (w.max(h) as f64);
                for p in shape.mesh().vertices() {
                    prop_assert!(p[0] >= -eps && p[1] >= -eps && p[0] <= w as f64 + eps && p[1] <= h as f64 + eps, "{:?}", p);
                }
                for uv in shape.uvs() {
                    prop_assert!((0.0..=1.0).contains(&uv[0]) && (0.0..=1.0).contains(&uv[1]), "{:?}", uv);
                }
                prop_assert_eq!(shape.uvs().len(), shape.mesh().vertices().len());
                valid_or_clear(Ok(shape.into_mesh()))?;
            }
            Err(Error::NoOpaquePixel { .. }) => {}
            Err(e) => return Err(TestCaseError::fail(format!("unexpected error: {e}"))),
        }
    }
}

proptest! {
    // 1000 cases by default (each a small drag); PROPTEST_CASES=n runs n.
    #![proptest_config(ProptestConfig {
        cases: std::env::var("PROPTEST_CASES").ok().and_then(|n| n.parse().ok()).unwrap_or(1000),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// The injective method from rest: random star-shaped shapes, two to four pins at
    /// random points, random far targets reached in a few updates with a tiny budget: no
    /// triangle ever has a non-positive area and no interior one-ring winds other than
    /// once, after any update. Pins placed on vertices make steps where a single vertex
    /// moves (the linear case of the largest step).
    #[test]
    fn injective_updates_never_fold(
        polar in prop::collection::vec((0.0f64..0.9, 0.5f64..2.0), 5..14),
        pins in prop::collection::vec((0.0f64..1.0, 0.0f64..1.0, -4.0f64..4.0, -4.0f64..4.0), 2..5),
        on_vertices in any::<bool>(),
        updates in 1usize..6,
    ) {
        let n = polar.len() as f64;
        let outer: Vec<[f64; 2]> = polar
            .iter()
            .enumerate()
            .map(|(k, &(jitter, r))| {
                let a = (k as f64 + jitter) / n * std::f64::consts::TAU;
                [r * a.cos(), r * a.sin()]
            })
            .collect();
        let mesh = mesh_outline(&outer, &[], &OutlineOptions::new().with_spacing(0.35)).unwrap();
        let rest = Rest::register(mesh.clone(), Options { budget_ms: 0.5, ..Options::default() }).unwrap();
        // Pins at points between the centre and random vertices, or on the vertices.
        let nv = mesh.vertices().len();
        let mut handles = Vec::new();
        let mut targets = Vec::new();
        for &(u, s, dx, dy) in &pins {
            let v = ((u * nv as f64) as usize).min(nv - 1);
            let p = mesh.vertices()[v];
            let h = if on_vertices { Handle::Vertex(v as u32) } else { Handle::Point([s * p[0], s * p[1]]) };
            if handles.contains(&h) {
                continue;
            }
            handles.push(h);
            targets.push((if on_vertices { p } else { [s * p[0], s * p[1]] }, [dx, dy]));
        }
        let Ok(mut pinned) = rest.compile(&handles) else { return Ok(()) }; // coincident pins
        for step in 1..=updates + 3 {
            let f = step.min(updates) as f64 / updates as f64;
            let t: Vec<[f64; 2]> = targets.iter().map(|(p, d)| [p[0] + f * d[0], p[1] + f * d[1]]).collect();
            let out = pinned.update(&t).unwrap().to_vec();
            let q = bunraku::quality::quality_2d(&mesh, &out).unwrap();
            prop_assert_eq!((q.flipped, q.winding_defects), (0, 0), "update {}", step);
        }
    }
}
