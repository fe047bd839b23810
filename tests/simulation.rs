//! The simulation mesh through the public API (issue "The default method at the paper's
//! speed, at any size"): a puppet document (version 2) that stores one round-trips bit for
//! bit and plays on it, exactly as a pin set compiled on the simulation mesh and gathered;
//! version 1 documents cannot hold one; and pins placed through the rendered mesh.
//! Native only: documents are read and written as JSON text natively.
#![cfg(not(target_arch = "wasm32"))]

use bunraku::animation::{
    Document, MeshJson, PinsJson, Player, PuppetJson, SimulationJson, Track, TrackOptions, FORMAT,
};
use bunraku::meshing::{shape_from_outline, OutlineOptions};
use bunraku::simulation::Embedding;
use bunraku::{Handle, Options, Pin, PinKind, Rest, Rotation};

/// A 60 × 20 bar meshed coarsely, refined 3 × 3: the rendered mesh and its simulation.
fn bar() -> bunraku::meshing::ShapeMesh {
    let outline = [[0.0, 0.0], [60.0, 0.0], [60.0, 20.0], [0.0, 20.0]];
    let coarse = shape_from_outline(&outline, &[], &OutlineOptions::new().with_spacing(5.0)).unwrap();
    coarse.refine(3).unwrap()
}

/// A document whose track bends the bar's right end up over 20 samples, on its simulation
/// mesh, with `method`.
fn document(method: &str) -> Document {
    let shape = bar();
    let s = shape.simulation().unwrap();
    let mut track = Track::new(vec![PinKind::Position, PinKind::Position], TrackOptions::default()).unwrap();
    for k in 0..=20 {
        let f = k as f64 / 20.0;
        track.record(f, &[[2.0, 10.0], [58.0, 10.0 + 15.0 * f]], None).unwrap();
    }
    let flat2 = |p: &[[f64; 2]]| p.iter().flatten().copied().collect::<Vec<f64>>();
    Document {
        format: FORMAT.into(),
        version: 2,
        picture: None,
        meshing: None,
        mesh: MeshJson {
            vertices: flat2(shape.mesh().vertices()),
            triangles: shape.mesh().triangles().iter().flatten().copied().collect(),
            uvs: None,
        },
        simulation: Some(SimulationJson {
            vertices: flat2(s.mesh().vertices()),
            triangles: s.mesh().triangles().iter().flatten().copied().collect(),
            parent: s.parent().to_vec(),
            weights: s.weights().iter().flatten().copied().collect(),
        }),
        puppet: Some(PuppetJson { method: Some(method.into()), ..PuppetJson::default() }),
        pins: Some(PinsJson { points: vec![2.0, 10.0, 58.0, 10.0], kinds: None, radius: None, parts: None }),
        starch: None,
        overlap: None,
        blend: None,
        poses: None,
        track: Some(track.to_json()),
        parts: None,
        atlas: None,
        glue: None,
        draw_order: None,
        draw_order_track: None,
        weights: None,
        tick: None,
        parameters: None,
        grids: None,
        channels: None,
        dynamics: None,
        play: None,
        looping: None,
        duration: None,
    }
}

#[test]
fn a_document_with_a_simulation_mesh_round_trips_bit_for_bit() {
    let d = document("two-step");
    let text = d.to_json();
    let back = Document::from_json(&text).unwrap();
    // Written as version 4 (typed arrays as base64), the same values.
    assert_eq!(back, Document { version: 4, ..d });
    assert_eq!(back.to_json(), text);
}

#[test]
fn a_document_plays_on_its_simulation_mesh_as_a_gathered_pin_set() {
    let d = document("two-step");
    let shape = bar();
    let embedding = Embedding::new(shape.mesh().clone(), shape.simulation().unwrap().clone()).unwrap();
    let rest = Rest::register(embedding.simulation().mesh().clone(), Options::two_step()).unwrap();
    let pins = [Pin::from(Handle::Point([2.0, 10.0])), Pin::from(Handle::Point([58.0, 10.0]))];
    let placed = embedding.place_pins(&pins).unwrap();
    let mut pinned = rest.compile_pins(&placed.pins).unwrap();
    let mut player = Player::new(d).unwrap();
    assert_eq!(player.mesh().vertices().len(), shape.mesh().vertices().len());
    let n = shape.mesh().vertices().len();
    let (mut got, mut want) = (vec![[0.0; 2]; n], vec![[0.0; 2]; n]);
    for k in [0, 5, 13, 20] {
        let f = k as f64 / 20.0;
        let targets = [[2.0, 10.0], [58.0, 10.0 + 15.0 * f]];
        let mut mapped = [[0.0; 2]; 2];
        placed.targets(&targets, &[Rotation::default(); 2], &mut mapped);
        embedding.gather(pinned.update(&mapped).unwrap(), &mut want);
        player.positions_into(f, &mut got).unwrap();
        assert_eq!(got, want, "sample {k}");
    }
    // The bar's end follows its pin: the rendered mesh moves, not only the simulation mesh.
    let end = got.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
    assert!(end > 30.0, "{end}");
}

#[test]
fn the_injective_method_plays_the_same_on_a_simulation_mesh_at_30_and_60_fps() {
    let d = document("injective");
    let n = d.mesh.vertices.len() / 2;
    let mut a = Player::new(d.clone()).unwrap();
    let mut b = Player::new(d).unwrap();
    let (mut pa, mut pb) = (vec![[0.0; 2]; n], vec![[0.0; 2]; n]);
    for j in 0..=60 {
        b.positions_into(j as f64 / 60.0, &mut pb).unwrap();
        if j % 2 == 0 {
            a.positions_into((j / 2) as f64 / 30.0, &mut pa).unwrap();
            assert_eq!(pa, pb, "t = {j}/60");
        }
    }
}

#[test]
fn a_version_1_document_cannot_hold_a_simulation_mesh_and_bad_ones_are_named() {
    let mut d = document("two-step");
    d.version = 1;
    let e = Player::new(d).unwrap_err();
    assert_eq!(e.code(), "bad-document", "{e}");
    let mut d = document("two-step");
    if let Some(s) = &mut d.simulation {
        s.parent[3] = 1_000_000;
    }
    assert_eq!(Player::new(d).unwrap_err().code(), "bad-simulation");
    let mut d = document("two-step");
    if let Some(s) = &mut d.simulation {
        s.weights.pop();
    }
    assert_eq!(Player::new(d).unwrap_err().code(), "bad-length");
}

/// `Σₖ w[k] · sim[triangles[parent[v]][k]]` per rendered vertex: the GPU gather's formula
/// (issue 26 §11), in the order the core sums.
fn gathered(s: &bunraku::simulation::Simulation, sim: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let corner = |v: usize, k: usize| sim[s.mesh().triangles()[s.parent()[v] as usize][k] as usize];
    let w = s.weights();
    let at = |v: usize, i: usize| {
        w[v][0] * corner(v, 0)[i] + w[v][1] * corner(v, 1)[i] + w[v][2] * corner(v, 2)[i]
    };
    (0..s.parent().len()).map(|v| [at(v, 0), at(v, 1)]).collect()
}

#[test]
fn the_simulation_positions_gathered_by_formula_are_the_played_positions() {
    for method in ["two-step", "injective"] {
        let mut player = Player::new(document(method)).unwrap();
        let mut twin = Player::new(document(method)).unwrap();
        let s = player.simulation().unwrap().clone();
        let mut want = vec![[0.0; 2]; s.parent().len()];
        for t in [0.0, 0.25, 0.6, 1.0, 1.5] {
            twin.positions_into(t, &mut want).unwrap();
            let sim = player.simulation_positions(t).unwrap().to_vec();
            assert_eq!(sim.len(), s.mesh().vertices().len());
            assert_eq!(gathered(&s, &sim), want, "{method} at t = {t}");
        }
        assert!(want.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max) > 30.0);
    }
}

#[test]
fn the_simulation_positions_refuse_a_bad_time_and_a_document_without_one() {
    let mut player = Player::new(document("two-step")).unwrap();
    assert_eq!(player.simulation_positions(f64::NAN).unwrap_err().code(), "bad-time");
    let mut d = document("two-step");
    d.simulation = None;
    let mut plain = Player::new(d).unwrap();
    assert!(plain.simulation().is_none());
    assert_eq!(plain.simulation_positions(0.5).unwrap_err().code(), "bad-simulation");
}

/// A rendered mesh carried by a simulation mesh may have up to `MAX_RENDERED_VERTICES`
/// (2²⁰) vertices, where a mesh solved on is limited to `MAX_VERTICES` (2¹⁷): `refine`
/// builds one above the solved limit, a puppet registers on it and updates, `Mesh::new`
/// refuses the same vertices, and `refine` still refuses more than 2²⁰ before any work.
#[test]
fn a_rendered_mesh_on_a_simulation_mesh_may_exceed_the_solved_mesh_limit() {
    use bunraku::limits::{MAX_RENDERED_VERTICES, MAX_VERTICES};
    let outline = [[0.0, 0.0], [300.0, 0.0], [300.0, 100.0], [0.0, 100.0]];
    let coarse = shape_from_outline(&outline, &[], &OutlineOptions::new().with_spacing(10.0)).unwrap();
    let k = ((2.4 * MAX_VERTICES as f64 / coarse.mesh().triangles().len() as f64).sqrt().ceil()) as u32;
    let fine = coarse.refine(k).unwrap();
    let n = fine.mesh().vertices().len();
    assert!(n > MAX_VERTICES && n <= MAX_RENDERED_VERTICES, "{n} rendered vertices");
    let refused = bunraku::Mesh::new(fine.mesh().vertices().to_vec(), fine.mesh().triangles().to_vec());
    assert!(matches!(refused, Err(bunraku::Error::TooMany { limit, .. }) if limit == MAX_VERTICES));
    let embedding = Embedding::new(fine.mesh().clone(), fine.simulation().unwrap().clone()).unwrap();
    let rest = Rest::register(embedding.simulation().mesh().clone(), Options::two_step()).unwrap();
    let pins = [Pin::from(Handle::Point([10.0, 50.0])), Pin::from(Handle::Point([290.0, 50.0]))];
    let placed = embedding.place_pins(&pins).unwrap();
    let mut pinned = rest.compile_pins(&placed.pins).unwrap();
    let mut mapped = [[0.0; 2]; 2];
    placed.targets(&[[10.0, 50.0], [290.0, 80.0]], &[Rotation::default(); 2], &mut mapped);
    let mut moved = vec![[0.0; 2]; n];
    embedding.gather(pinned.update(&mapped).unwrap(), &mut moved);
    assert!(moved.iter().all(|p| p[0].is_finite() && p[1].is_finite()));
    assert!(moved.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max) > 75.0);
    // 2²⁰ / (k² · t) more than that: refused from the count, before any work.
    let too_fine = ((1.1 * MAX_RENDERED_VERTICES as f64 * 2.0 / coarse.mesh().triangles().len() as f64)
        .sqrt()
        .ceil()) as u32;
    assert!(too_fine <= 64, "{too_fine}");
    assert!(coarse.refine(too_fine).is_err());
}
