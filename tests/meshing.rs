//! Tests of `bunraku::meshing`: quality meshes of outlines with holes.
//!
//! The large meshes (30k and 100k vertices) are `#[ignore]`d; run them, with timings, by
//! `cargo test --release --test meshing -- --ignored --nocapture`.

use std::time::Instant;

use bunraku::meshing::{estimate_vertices, mesh_outline, spacing_for_vertices, star, OutlineOptions};
use bunraku::{Error, Mesh};

fn square(x0: f64, y0: f64, side: f64) -> Vec<[f64; 2]> {
    vec![[x0, y0], [x0 + side, y0], [x0 + side, y0 + side], [x0, y0 + side]]
}

fn circle(cx: f64, cy: f64, r: f64, n: usize) -> Vec<[f64; 2]> {
    (0..n)
        .map(|k| {
            let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            [cx + r * a.cos(), cy + r * a.sin()]
        })
        .collect()
}

fn polygon_area(p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    (0..n).map(|k| p[k][0] * p[(k + 1) % n][1] - p[k][1] * p[(k + 1) % n][0]).sum::<f64>() / 2.0
}

/// The area of a star from `star(points, inner, outer)`.
fn star_area(points: usize, inner: f64, outer: f64) -> f64 {
    points as f64 * inner * outer * (std::f64::consts::PI / points as f64).sin()
}

fn star_perimeter(points: usize, inner: f64, outer: f64) -> f64 {
    let s = star(points, inner, outer);
    let n = s.len();
    (0..n).map(|k| (s[(k + 1) % n][0] - s[k][0]).hypot(s[(k + 1) % n][1] - s[k][1])).sum()
}

fn corners(mesh: &Mesh, t: usize) -> [[f64; 2]; 3] {
    mesh.triangles()[t].map(|v| mesh.vertices()[v as usize])
}

fn triangle_area(p: [[f64; 2]; 3]) -> f64 {
    ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0])) / 2.0
}

fn mesh_area(mesh: &Mesh) -> f64 {
    (0..mesh.triangles().len()).map(|t| triangle_area(corners(mesh, t))).sum()
}

fn centroid(p: [[f64; 2]; 3]) -> [f64; 2] {
    [(p[0][0] + p[1][0] + p[2][0]) / 3.0, (p[0][1] + p[1][1] + p[2][1]) / 3.0]
}

fn inside(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let mut odd = false;
    let n = poly.len();
    for k in 0..n {
        let (a, b) = (poly[k], poly[(k + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]) {
            odd = !odd;
        }
    }
    odd
}

/// Smallest angle of each triangle, in degrees.
fn min_angles(mesh: &Mesh) -> Vec<f64> {
    (0..mesh.triangles().len())
        .map(|t| {
            let p = corners(mesh, t);
            (0..3)
                .map(|k| {
                    let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
                    let (u, w) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
                    (u[0] * w[1] - u[1] * w[0]).abs().atan2(u[0] * w[0] + u[1] * w[1]).to_degrees()
                })
                .fold(180.0, f64::min)
        })
        .collect()
}

/// Fraction of triangles whose smallest angle is at least `degrees`.
fn fraction_at_least(mesh: &Mesh, degrees: f64) -> f64 {
    let a = min_angles(mesh);
    a.iter().filter(|&&x| x >= degrees).count() as f64 / a.len() as f64
}

/// Checks the common guarantees: the first vertices are the outline's points, bit-exact;
/// no triangle outside `outer` or inside a hole; the area is right; the angles are good.
fn check_mesh(mesh: &Mesh, outer: &[[f64; 2]], holes: &[Vec<[f64; 2]>]) {
    let outline: Vec<[f64; 2]> = outer.iter().chain(holes.iter().flatten()).copied().collect();
    assert_eq!(&mesh.vertices()[..outline.len()], &outline[..], "outline points first, exact");
    for t in 0..mesh.triangles().len() {
        let c = centroid(corners(mesh, t));
        assert!(inside(c, outer), "triangle {t} (centroid {c:?}) lies outside the outer outline");
        for (h, hole) in holes.iter().enumerate() {
            assert!(!inside(c, hole), "triangle {t} (centroid {c:?}) lies inside hole {h}");
        }
    }
    let expected = polygon_area(outer).abs() - holes.iter().map(|h| polygon_area(h).abs()).sum::<f64>();
    let area = mesh_area(mesh);
    assert!((area - expected).abs() <= 1e-9 * expected, "area {area}, expected {expected}");
    assert_eq!(mesh.component_count(), 1);
    let good = fraction_at_least(mesh, 20.0);
    assert!(good >= 0.99, "only {:.2}% of triangles have all angles ≥ 20°", 100.0 * good);
}

/// An outer outline and its holes.
type Shape = (Vec<[f64; 2]>, Vec<Vec<[f64; 2]>>);

fn bad_outline(result: Result<Mesh, Error>) -> String {
    match result {
        Err(Error::BadOutline { reason }) => reason,
        other => panic!("expected Error::BadOutline, got {other:?}"),
    }
}

/// The message of an [`Error::BadOption`] for `option` (which names the offending value,
/// if any, and the reason).
fn bad_option(result: Result<Mesh, Error>, option: &str) -> String {
    match result {
        Err(e @ Error::BadOption { name, .. }) if name == option => e.to_string(),
        other => panic!("expected Error::BadOption for {option}, got {other:?}"),
    }
}

#[test]
fn unit_square() {
    let outer = square(0.0, 0.0, 1.0);
    let mesh = mesh_outline(&outer, &[], &OutlineOptions::new().with_spacing(0.1)).unwrap();
    check_mesh(&mesh, &outer, &[]);
    assert!(mesh.vertices().iter().all(|p| (0.0..=1.0).contains(&p[0]) && (0.0..=1.0).contains(&p[1])));
    // Boundary edges lie on the square's sides and are no longer than the spacing.
    for e in mesh.boundary_edges() {
        let (a, b) = (mesh.vertices()[e.i as usize], mesh.vertices()[e.j as usize]);
        assert!(a[0] == b[0] && (a[0] == 0.0 || a[0] == 1.0) || a[1] == b[1] && (a[1] == 0.0 || a[1] == 1.0));
        assert!((b[0] - a[0]).hypot(b[1] - a[1]) <= 0.1 + 1e-12);
    }
    // All angles are at least 30° here (no sharp input corner).
    assert!(min_angles(&mesh).iter().all(|&a| a >= 29.9));
    // Largest triangle within the area bound.
    let max_area =
        (0..mesh.triangles().len()).map(|t| triangle_area(corners(&mesh, t)).abs()).fold(0.0, f64::max);
    assert!(max_area <= 3f64.sqrt() / 4.0 * 0.01 * (1.0 + 1e-9));
}

#[test]
fn default_spacing_is_a_fortieth_of_the_diagonal() {
    let outer = square(0.0, 0.0, 1.0);
    let default = mesh_outline(&outer, &[], &OutlineOptions::default()).unwrap();
    let explicit =
        mesh_outline(&outer, &[], &OutlineOptions::new().with_spacing(2f64.sqrt() / 40.0)).unwrap();
    assert_eq!(default.vertices().len(), explicit.vertices().len());
    assert_eq!(default.triangles(), explicit.triangles());
}

#[test]
fn five_pointed_star() {
    let outer = star(5, 0.5, 1.0);
    assert_eq!(outer.len(), 10);
    assert!((polygon_area(&outer) - star_area(5, 0.5, 1.0)).abs() < 1e-12);
    let mesh = mesh_outline(&outer, &[], &OutlineOptions::new().with_spacing(0.05)).unwrap();
    check_mesh(&mesh, &outer, &[]);
}

#[test]
fn sharp_star_keeps_quality_away_from_its_tips() {
    // Twelve tips of about 12.5°: only triangles at the tips may be worse than 20°.
    let outer = star(12, 0.3, 1.0);
    let mesh = mesh_outline(&outer, &[], &OutlineOptions::new().with_spacing(0.02)).unwrap();
    check_mesh(&mesh, &outer, &[]);
}

#[test]
fn square_with_holes() {
    let outer = square(0.0, 0.0, 4.0);
    // A clockwise square hole and a counter-clockwise round one: orientation is free.
    let mut hole0 = square(0.5, 0.5, 1.0);
    hole0.reverse();
    let hole1 = circle(2.7, 2.7, 0.8, 48);
    let holes = vec![hole0, hole1];
    let mesh = mesh_outline(&outer, &holes, &OutlineOptions::new().with_spacing(0.1)).unwrap();
    check_mesh(&mesh, &outer, &holes);
    // The outer loop and the two holes make three boundary loops.
    let boundary: Vec<_> = mesh.boundary_edges().collect();
    let expected = 4 * 40 + 4 * 10; // subdivided square sides
    assert!(boundary.len() >= expected + 48, "{} boundary edges", boundary.len());
}

#[test]
fn star_with_star_hole() {
    let outer = star(7, 0.6, 1.0);
    let hole: Vec<[f64; 2]> = star(5, 0.15, 0.3).into_iter().map(|p| [p[0] + 0.05, p[1] - 0.02]).collect();
    let holes = vec![hole];
    let mesh = mesh_outline(&outer, &holes, &OutlineOptions::new().with_spacing(0.03)).unwrap();
    check_mesh(&mesh, &outer, &holes);
}

#[test]
fn angle_quality_over_shapes_and_spacings() {
    let shapes: Vec<Shape> = vec![
        (square(0.0, 0.0, 1.0), vec![]),
        (star(5, 0.5, 1.0), vec![]),
        (star(9, 0.7, 1.0), vec![circle(0.0, 0.0, 0.3, 30)]),
        (circle(0.0, 0.0, 1.0, 200), vec![square(-0.2, -0.2, 0.4)]),
        // A thin L.
        (vec![[0.0, 0.0], [3.0, 0.0], [3.0, 0.2], [0.2, 0.2], [0.2, 2.0], [0.0, 2.0]], vec![]),
    ];
    for (outer, holes) in &shapes {
        for spacing in [0.2, 0.07, 0.03] {
            let options = OutlineOptions::new().with_spacing(spacing);
            let mesh = mesh_outline(outer, holes, &options).unwrap();
            check_mesh(&mesh, outer, holes);
        }
        let mesh = mesh_outline(outer, holes, &OutlineOptions::new().with_min_angle_deg(20.0)).unwrap();
        check_mesh(&mesh, outer, holes);
    }
}

#[test]
fn every_outline_point_is_kept_after_cleaning() {
    // A repeated closing point and consecutive duplicates are dropped; the rest are kept
    // exactly, in order.
    let raw =
        vec![[0.0, 0.0], [0.3, 0.0], [0.3, 0.0], [1.0, 0.0], [1.0, 0.7], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0]];
    let cleaned = vec![[0.0, 0.0], [0.3, 0.0], [1.0, 0.0], [1.0, 0.7], [1.0, 1.0], [0.0, 1.0]];
    let hole_raw = vec![[0.4, 0.4], [0.4, 0.4], [0.6, 0.4], [0.6, 0.6], [0.4, 0.6], [0.4, 0.4]];
    let hole = vec![[0.4, 0.4], [0.6, 0.4], [0.6, 0.6], [0.4, 0.6]];
    let mesh = mesh_outline(&raw, &[hole_raw], &OutlineOptions::new().with_spacing(0.08)).unwrap();
    check_mesh(&mesh, &cleaned, &[hole]);
    // Irregular outline points (not on the spacing grid) are kept too.
    let outer = circle(0.1, -0.2, 1.3, 77);
    let mesh = mesh_outline(&outer, &[], &OutlineOptions::new().with_spacing(0.3)).unwrap();
    for p in &outer {
        assert!(mesh.vertices().contains(p));
    }
}

#[test]
fn vertex_budget_holds() {
    let outer = star(5, 0.5, 1.0);
    let unbounded = mesh_outline(&outer, &[], &OutlineOptions::new().with_spacing(0.02)).unwrap();
    assert!(unbounded.vertices().len() > 6000);
    for budget in [3000, 1000, 200, 40, 12, 10] {
        let options = OutlineOptions::new().with_spacing(0.02).with_max_vertices(budget);
        let mesh = mesh_outline(&outer, &[], &options).unwrap();
        let n = mesh.vertices().len();
        assert!(n <= budget, "budget {budget}: {n} vertices");
        if budget >= 200 {
            // The spacing is enlarged just enough: the budget is mostly used.
            assert!(n as f64 >= 0.7 * budget as f64, "budget {budget}: only {n} vertices");
            check_mesh(&mesh, &outer, &[]);
        }
    }
    // A budget above the natural count changes nothing.
    let options = OutlineOptions::new().with_spacing(0.02).with_max_vertices(100_000);
    let mesh = mesh_outline(&outer, &[], &options).unwrap();
    assert_eq!(mesh.vertices().len(), unbounded.vertices().len());
    // A budget with holes, and with sharp tips that need extra vertices.
    let holes = vec![circle(0.0, 0.0, 0.2, 40)];
    for (outer, holes) in [(star(12, 0.3, 1.0), vec![]), (star(6, 0.6, 1.0), holes)] {
        for budget in [500, 2000] {
            let options = OutlineOptions::new().with_spacing(0.005).with_max_vertices(budget);
            let n = mesh_outline(&outer, &holes, &options).unwrap().vertices().len();
            assert!(n <= budget && n as f64 >= 0.6 * budget as f64, "budget {budget}: {n} vertices");
        }
    }
}

#[test]
fn vertex_count_scales_with_spacing() {
    let outer = star(5, 0.5, 1.0);
    let (area, perimeter) = (star_area(5, 0.5, 1.0), star_perimeter(5, 0.5, 1.0));
    let mut last = 0;
    for spacing in [0.2, 0.1, 0.05, 0.025] {
        let n =
            mesh_outline(&outer, &[], &OutlineOptions::new().with_spacing(spacing)).unwrap().vertices().len();
        let estimate = estimate_vertices(area, perimeter, spacing);
        println!("spacing {spacing}: {n} vertices (estimate {estimate:.0})");
        // Within 10% once the mesh has more than a few hundred vertices.
        let tolerance = if n > 300 { 0.1 } else { 0.25 };
        assert!((n as f64 - estimate).abs() <= tolerance * estimate, "spacing {spacing}: {n} vs {estimate}");
        if last > 0 {
            // Halving the spacing gives 3–4.5 times the vertices.
            let ratio = n as f64 / last as f64;
            assert!((3.0..=4.5).contains(&ratio), "ratio {ratio}");
        }
        last = n;
    }
}

#[test]
fn scale_and_translation_do_not_matter() {
    let outer = star(5, 0.5, 1.0);
    let reference = mesh_outline(&outer, &[], &OutlineOptions::new().with_spacing(0.05)).unwrap();
    for (scale, shift) in [(1e6, 3e7), (1e-6, -2e-5), (1e-150, 0.0), (1e150, 1e151)] {
        let moved: Vec<[f64; 2]> = outer.iter().map(|p| [p[0] * scale + shift, p[1] * scale]).collect();
        let options = OutlineOptions::new().with_spacing(0.05 * scale);
        let mesh = mesh_outline(&moved, &[], &options).unwrap();
        let n = reference.vertices().len() as f64;
        assert!(
            (mesh.vertices().len() as f64 - n).abs() <= 0.02 * n,
            "scale {scale}: {}",
            mesh.vertices().len()
        );
        assert_eq!(&mesh.vertices()[..10], &moved[..]);
    }
}

/// A mesh of about `target` vertices from `star(5, 0.5, 1.0)`, with
/// [`spacing_for_vertices`], timed.
fn star_mesh_of(target: usize) -> Mesh {
    let outer = star(5, 0.5, 1.0);
    let spacing = spacing_for_vertices(star_area(5, 0.5, 1.0), target);
    let start = Instant::now();
    let mesh = mesh_outline(&outer, &[], &OutlineOptions::new().with_spacing(spacing)).unwrap();
    let n = mesh.vertices().len();
    println!(
        "star(5, 0.5, 1.0), spacing {spacing:.5}: {n} vertices, {} triangles in {:.3} s",
        mesh.triangles().len(),
        start.elapsed().as_secs_f64()
    );
    // The interior term is the target; the boundary adds about P/s (under 10% here).
    assert!(n as f64 >= 0.95 * target as f64 && n as f64 <= 1.12 * target as f64, "{n} for {target}");
    check_mesh(&mesh, &outer, &[]);
    mesh
}

#[test]
fn star_3k() {
    star_mesh_of(3_000);
}

#[test]
#[ignore = "large: run with --release -- --ignored"]
fn star_30k() {
    star_mesh_of(30_000);
}

#[test]
#[ignore = "large: run with --release -- --ignored"]
fn star_100k() {
    star_mesh_of(100_000);
}

#[test]
fn budget_on_a_large_request_is_fast() {
    // A tiny spacing with a budget never builds the tiny-spacing mesh.
    let options = OutlineOptions::new().with_spacing(1e-6).with_max_vertices(2000);
    let mesh = mesh_outline(&star(5, 0.5, 1.0), &[], &options).unwrap();
    assert!(mesh.vertices().len() <= 2000);
}

#[test]
fn too_few_points() {
    let opts = OutlineOptions::default();
    assert!(bad_outline(mesh_outline(&[], &[], &opts)).contains("0 distinct points"));
    assert!(bad_outline(mesh_outline(&[[0.0, 0.0], [1.0, 0.0]], &[], &opts)).contains("2 distinct points"));
    let r = bad_outline(mesh_outline(&[[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 0.0]], &[], &opts));
    assert!(r.contains("outer outline has 2 distinct points"), "{r}");
    let hole = vec![[0.2, 0.2], [0.2, 0.2], [0.2, 0.2]];
    let r = bad_outline(mesh_outline(&square(0.0, 0.0, 1.0), &[hole], &opts));
    assert!(r.contains("hole 0 has 1 distinct points"), "{r}");
}

#[test]
fn non_finite_points() {
    let opts = OutlineOptions::default();
    let mut outer = square(0.0, 0.0, 1.0);
    outer[2][1] = f64::NAN;
    let r = bad_outline(mesh_outline(&outer, &[], &opts));
    assert!(r.contains("point 2 of the outer outline is not finite"), "{r}");
    let mut hole = square(0.2, 0.2, 0.5);
    hole[3][0] = f64::INFINITY;
    let r = bad_outline(mesh_outline(&square(0.0, 0.0, 1.0), &[square(0.1, 0.1, 0.05), hole], &opts));
    assert!(r.contains("point 3 of the hole 1 is not finite"), "{r}");
}

#[test]
fn zero_area() {
    let opts = OutlineOptions::default();
    let r = bad_outline(mesh_outline(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]], &[], &opts));
    assert_eq!(r, "the outer outline has zero area (its points are collinear)");
    let r = bad_outline(mesh_outline(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.5, 0.0]], &[], &opts));
    assert!(r.contains("outer outline has zero area"), "{r}");
    // Below working precision: a sliver 1e-14 of its length thick.
    let r = bad_outline(mesh_outline(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1e-14], [0.5, 1e-14]], &[], &opts));
    assert!(r.contains("outer outline has zero area"), "{r}");
    let hole = vec![[0.2, 0.2], [0.4, 0.4], [0.6, 0.6]];
    let r = bad_outline(mesh_outline(&square(0.0, 0.0, 1.0), &[hole], &opts));
    assert!(r.contains("hole 0 has zero area"), "{r}");
}

#[test]
fn self_intersections() {
    let opts = OutlineOptions::default();
    // A bow tie: segment 0 (0→1) crosses segment 2 (2→3).
    let r = bad_outline(mesh_outline(&[[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]], &[], &opts));
    assert_eq!(r, "segment 0 (points 0→1) of the outer outline crosses or touches segment 2 (points 2→3) of the outer outline");
    // A spike that folds back onto the previous segment.
    let r = bad_outline(mesh_outline(&[[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]], &[], &opts));
    assert!(r.contains("segment 0 (points 0→1)") && r.contains("segment 1 (points 1→2)"), "{r}");
    // A vertex touching another segment.
    let touch = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [1.0, 0.0], [0.0, 2.0]];
    let r = bad_outline(mesh_outline(&touch, &[], &opts));
    assert!(r.contains("crosses or touches"), "{r}");
    // Indices name the input points, before duplicates were dropped.
    let r =
        bad_outline(mesh_outline(&[[0.0, 0.0], [0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]], &[], &opts));
    assert_eq!(r, "segment 0 (points 0→2) of the outer outline crosses or touches segment 2 (points 3→4) of the outer outline");
    // A hole crossing the outer outline.
    let r = bad_outline(mesh_outline(&square(0.0, 0.0, 1.0), &[square(0.5, 0.5, 1.0)], &opts));
    assert!(r.contains("of the outer outline crosses or touches") && r.contains("of the hole 0"), "{r}");
    // Two crossing holes.
    let holes = vec![square(0.1, 0.1, 0.4), square(0.3, 0.3, 0.4)];
    let r = bad_outline(mesh_outline(&square(0.0, 0.0, 1.0), &holes, &opts));
    assert!(r.contains("of the hole 0 crosses or touches") && r.contains("of the hole 1"), "{r}");
    // A hole touching the outer outline at a vertex.
    let hole = vec![[0.0, 0.0], [0.5, 0.2], [0.2, 0.5]];
    let r = bad_outline(mesh_outline(&square(0.0, 0.0, 1.0), &[hole], &opts));
    assert!(r.contains("crosses or touches"), "{r}");
    // A big zigzag: the sweep finds the one crossing among thousands of segments.
    let mut zigzag = circle(0.0, 0.0, 1.0, 4000);
    zigzag.swap(1000, 1001);
    let r = bad_outline(mesh_outline(&zigzag, &[], &opts));
    assert!(
        r.contains("segment 999 (points 999→1000)") && r.contains("segment 1001 (points 1001→1002)"),
        "{r}"
    );
}

#[test]
fn points_closer_than_working_precision() {
    // 1e-300 is lost against the unit square's size.
    let outer = [[0.0, 0.0], [1e-300, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let r = bad_outline(mesh_outline(&outer, &[], &OutlineOptions::default()));
    assert_eq!(r, "points 0 and 1 of the outer outline are too close to tell apart");
}

#[test]
fn misplaced_holes() {
    let opts = OutlineOptions::default();
    let r = bad_outline(mesh_outline(&square(0.0, 0.0, 1.0), &[square(2.0, 2.0, 0.5)], &opts));
    assert_eq!(r, "the hole 0 is not inside the outer outline");
    // Inside the bounding box but outside the star.
    let r = bad_outline(mesh_outline(&star(5, 0.3, 1.0), &[square(0.8, -0.9, 0.05)], &opts));
    assert_eq!(r, "the hole 0 is not inside the outer outline");
    // The outer outline inside a "hole".
    let r = bad_outline(mesh_outline(&square(0.4, 0.4, 0.2), &[square(0.0, 0.0, 1.0)], &opts));
    assert_eq!(r, "the hole 0 is not inside the outer outline");
    let holes = vec![square(0.1, 0.1, 0.8), square(0.3, 0.3, 0.2)];
    let r = bad_outline(mesh_outline(&square(0.0, 0.0, 1.0), &holes, &opts));
    assert_eq!(r, "the hole 1 lies inside the hole 0");
}

#[test]
fn bad_options() {
    let outer = square(0.0, 0.0, 1.0);
    for spacing in [0.0, -0.1, f64::NAN, f64::INFINITY] {
        let r =
            bad_option(mesh_outline(&outer, &[], &OutlineOptions::new().with_spacing(spacing)), "spacing");
        assert!(r.starts_with(&format!("option spacing: {spacing} ")), "{r}");
    }
    // Far too fine for the vertex limit.
    let r = bad_option(mesh_outline(&outer, &[], &OutlineOptions::new().with_spacing(1e-9)), "spacing");
    assert!(r.contains("more than the limit"), "{r}");
    for angle in [0.0, -5.0, 33.5, 60.0, f64::NAN] {
        bad_option(
            mesh_outline(&outer, &[], &OutlineOptions::new().with_min_angle_deg(angle)),
            "min_angle_deg",
        );
    }
    assert!(mesh_outline(&outer, &[], &OutlineOptions::new().with_min_angle_deg(33.0)).is_ok());
    let r = bad_option(
        mesh_outline(&star(5, 0.5, 1.0), &[], &OutlineOptions::new().with_max_vertices(9)),
        "max_vertices",
    );
    assert!(r.contains("10 distinct outline points"), "{r}");
}

#[test]
fn errors_display() {
    let e = mesh_outline(&[[0.0, 0.0]], &[], &OutlineOptions::default()).unwrap_err();
    assert_eq!(e.to_string(), "bad outline: the outer outline has 1 distinct points; at least 3 are needed");
}
