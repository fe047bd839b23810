use super::refine::{refine, refined_vertex_count};
use super::*;
use crate::meshing::{mesh_image, shape_from_outline, star, test_character, ImageOptions, OutlineOptions};

/// A small deterministic generator (xorshift), so that the tests need no crate.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn det(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

fn star_mesh(spacing: f64) -> Mesh {
    shape_from_outline(
        &star(5, 0.5, 1.0),
        &[],
        &OutlineOptions::new().with_spacing(spacing).with_simulation_vertices(0),
    )
    .unwrap()
    .into_mesh()
}

#[test]
fn refinement_is_conforming_and_counted() {
    let mesh = star_mesh(0.2);
    for k in 1..=5 {
        let (rendered, simulation) = refine(&mesh, k).unwrap();
        assert_eq!(rendered.vertices().len(), refined_vertex_count(&mesh, k));
        assert_eq!(rendered.triangles().len(), mesh.triangles().len() * (k * k) as usize);
        // Conforming: the same boundary length, one component, as many loops.
        assert_eq!(rendered.component_count(), mesh.component_count());
        assert_eq!(rendered.boundary_loops().len(), mesh.boundary_loops().len());
        assert_eq!(rendered.boundary_edges().count(), k as usize * mesh.boundary_edges().count());
        assert_eq!(simulation.home().len(), rendered.triangles().len());
    }
}

#[test]
fn every_rendered_triangle_lies_in_its_home() {
    let mesh = star_mesh(0.15);
    let (rendered, simulation) = refine(&mesh, 4).unwrap();
    for (tri, &s) in rendered.triangles().iter().zip(simulation.home()) {
        let parent = mesh.triangles()[s as usize].map(|v| mesh.vertices()[v as usize]);
        for &v in tri {
            let w = crate::locate::barycentric(parent, rendered.vertices()[v as usize]);
            assert!(w.iter().all(|&x| x >= -1e-12), "{w:?}");
        }
    }
}

#[test]
fn the_gather_reproduces_each_parents_affine_map() {
    let mesh = star_mesh(0.2);
    let (rendered, simulation) = refine(&mesh, 3).unwrap();
    let mut rng = Rng(7);
    // A random affine map of the whole simulation mesh: every rendered vertex follows it.
    let m = [rng.next() + 0.5, rng.next() - 0.5, rng.next() - 0.5, rng.next() + 0.5, rng.next(), rng.next()];
    let map = |p: [f64; 2]| [m[0] * p[0] + m[1] * p[1] + m[4], m[2] * p[0] + m[3] * p[1] + m[5]];
    let simulated: Vec<[f64; 2]> = mesh.vertices().iter().map(|&p| map(p)).collect();
    let mut out = vec![[0.0; 2]; rendered.vertices().len()];
    simulation.gather(&simulated, &mut out);
    for (o, &r) in out.iter().zip(rendered.vertices()) {
        let e = map(r);
        assert!((o[0] - e[0]).abs() < 1e-12 && (o[1] - e[1]).abs() < 1e-12);
    }
    // A random piecewise-linear map: each rendered triangle follows its home's own map.
    let simulated: Vec<[f64; 2]> =
        mesh.vertices().iter().map(|p| [p[0] + 0.05 * rng.next(), p[1] + 0.05 * rng.next()]).collect();
    simulation.gather(&simulated, &mut out);
    for (tri, &s) in rendered.triangles().iter().zip(simulation.home()) {
        let parent = mesh.triangles()[s as usize];
        let rest = parent.map(|v| mesh.vertices()[v as usize]);
        for &v in tri {
            let w = crate::locate::barycentric(rest, rendered.vertices()[v as usize]);
            let mut e = [0.0; 2];
            for (k, &u) in parent.iter().enumerate() {
                e[0] += w[k] * simulated[u as usize][0];
                e[1] += w[k] * simulated[u as usize][1];
            }
            let o = out[v as usize];
            assert!((o[0] - e[0]).abs() < 1e-12 && (o[1] - e[1]).abs() < 1e-12);
        }
    }
}

/// Random injective simulation poses (every simulation triangle positive) give no inverted
/// rendered triangle: the nesting's guarantee, on a refinement and on a snapped picture.
#[test]
fn injective_parent_maps_give_no_inverted_rendered_triangle() {
    let picture = test_character(400, 400);
    let options =
        ImageOptions { spacing: Some(1.5), simulation_vertices: Some(600), ..ImageOptions::default() };
    let shape = mesh_image(&picture, 400, 400, &options).unwrap();
    let snapped = (shape.mesh().clone(), shape.simulation().unwrap().clone());
    let plain = refine(&star_mesh(0.1), 5).unwrap();
    let mut rng = Rng(42);
    for (rendered, simulation) in [plain, snapped] {
        let sim = simulation.mesh();
        let mut checked = 0;
        for round in 0..40 {
            // A random jitter up to a third of a typical edge, kept when injective.
            let amplitude = 0.3 * sim.diameter() / (sim.vertices().len() as f64).sqrt();
            let x: Vec<[f64; 2]> = sim
                .vertices()
                .iter()
                .map(|p| {
                    let a = 2.0 * std::f64::consts::PI * rng.next();
                    let r = amplitude * rng.next() * (round as f64 / 40.0);
                    [p[0] + r * a.cos(), p[1] + r * a.sin()]
                })
                .collect();
            if sim
                .triangles()
                .iter()
                .any(|t| det(x[t[0] as usize], x[t[1] as usize], x[t[2] as usize]) <= 0.0)
            {
                continue;
            }
            checked += 1;
            let mut out = vec![[0.0; 2]; simulation.rendered_count()];
            simulation.gather(&x, &mut out);
            let inverted = rendered
                .triangles()
                .iter()
                .filter(|t| det(out[t[0] as usize], out[t[1] as usize], out[t[2] as usize]) <= 0.0)
                .count();
            assert_eq!(inverted, 0, "round {round}");
        }
        assert!(checked >= 5, "only {checked} injective poses");
    }
}

#[test]
fn bad_embeddings_are_rejected_with_their_codes() {
    let mesh = star_mesh(0.3);
    let (rendered, simulation) = refine(&mesh, 2).unwrap();
    let (parent, weights) = (simulation.parent().to_vec(), simulation.weights().to_vec());
    let code =
        |p: Vec<u32>, w: Vec<[f64; 3]>| Simulation::new(mesh.clone(), p, w, &rendered).unwrap_err().code();
    assert!(Simulation::new(mesh.clone(), parent.clone(), weights.clone(), &rendered).is_ok());
    assert_eq!(code(parent[1..].to_vec(), weights.clone()), "bad-length");
    assert_eq!(code(parent.clone(), weights[1..].to_vec()), "bad-length");
    let mut p = parent.clone();
    p[3] = mesh.triangles().len() as u32;
    assert_eq!(code(p, weights.clone()), "bad-simulation");
    let mut w = weights.clone();
    w[5] = [0.5, 0.6, 0.0];
    assert_eq!(code(parent.clone(), w), "bad-simulation");
    let mut w = weights.clone();
    w[5][0] = f64::NAN;
    assert_eq!(code(parent.clone(), w), "non-finite");
    // Weights that sum to 1 but put the vertex elsewhere.
    let mut w = weights.clone();
    w[7] = [1.0, 0.0, 0.0];
    w[7] = if weights[7] == w[7] { [0.0, 1.0, 0.0] } else { w[7] };
    assert_eq!(code(parent.clone(), w), "bad-simulation");
    // A rendered triangle whose vertices are read in unrelated triangles: not nested.
    let far = (0..mesh.triangles().len() as u32)
        .find(|&t| {
            !mesh.triangles()[t as usize].iter().any(|v| mesh.triangles()[parent[0] as usize].contains(v))
        })
        .unwrap();
    let mut p = parent.clone();
    let mut w = weights.clone();
    let tri = mesh.triangles()[far as usize].map(|v| mesh.vertices()[v as usize]);
    // Vertex 0 expressed (extrapolated) in a far triangle: the right position, the wrong parent.
    p[0] = far;
    w[0] = crate::locate::barycentric(tri, rendered.vertices()[0]);
    let e = Simulation::new(mesh.clone(), p, w, &rendered).unwrap_err();
    assert_eq!(e.code(), "bad-simulation", "{e}");
}

/// The snapped picture: every rendered boundary vertex lies on the traced outline, and the
/// outline lies within half a pixel of the rendered boundary.
#[test]
fn the_snapped_silhouette_lies_on_the_outline() {
    let picture = test_character(512, 512);
    let base = ImageOptions { spacing: Some(2.0), ..ImageOptions::default() };
    let fine = mesh_image(
        &picture,
        512,
        512,
        &ImageOptions { simulation_vertices: Some(0), spacing: Some(40.0), ..base.clone() },
    )
    .unwrap();
    let nested =
        mesh_image(&picture, 512, 512, &ImageOptions { simulation_vertices: Some(1500), ..base }).unwrap();
    assert!(nested.simulation().is_some());
    let segments = |shape: &crate::meshing::ShapeMesh| -> Vec<([f64; 2], [f64; 2])> {
        let v = shape.mesh().vertices();
        shape
            .boundary()
            .iter()
            .flat_map(|l| (0..l.len()).map(move |k| (v[l[k] as usize], v[l[(k + 1) % l.len()] as usize])))
            .collect()
    };
    let distance = |p: [f64; 2], segs: &[([f64; 2], [f64; 2])]| {
        segs.iter()
            .map(|&(a, b)| {
                let ab = [b[0] - a[0], b[1] - a[1]];
                let len2 = ab[0] * ab[0] + ab[1] * ab[1];
                let t = if len2 > 0.0 {
                    (((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (p[0] - a[0] - t * ab[0]).hypot(p[1] - a[1] - t * ab[1])
            })
            .fold(f64::INFINITY, f64::min)
    };
    let (outline, silhouette) = (segments(&fine), segments(&nested));
    let on = silhouette.iter().map(|s| distance(s.0, &outline)).fold(0.0, f64::max);
    let back = outline.iter().map(|s| distance(s.0, &silhouette)).fold(0.0, f64::max);
    assert!(on < 1e-9, "a rendered boundary vertex lies {on} px off the outline");
    assert!(back <= 0.5, "an outline point lies {back} px from the silhouette");
}
