use bunraku::{Handle, Mesh, Options, Rest};

fn grid(nx: usize, ny: usize) -> Mesh {
    let mut v = vec![];
    for y in 0..=ny {
        for x in 0..=nx {
            v.push([x as f64, y as f64]);
        }
    }
    let id = |x: usize, y: usize| (y * (nx + 1) + x) as u32;
    let mut t = vec![];
    for y in 0..ny {
        for x in 0..nx {
            t.push([id(x, y), id(x + 1, y), id(x + 1, y + 1)]);
            t.push([id(x, y), id(x + 1, y + 1), id(x, y + 1)]);
        }
    }
    Mesh::new(v, t).unwrap()
}

#[test]
fn smoke_rigid() {
    let mesh = grid(10, 6);
    let rest = Rest::register(mesh.clone(), Options::default()).unwrap();
    let hs = [[0.5, 0.5], [9.3, 0.2], [5.0, 5.5], [2.2, 4.1]];
    let mut p = rest.compile(&hs.map(Handle::Point)).unwrap();
    let (c, s) = (0.6f64.cos(), 0.6f64.sin());
    let m = |q: [f64; 2]| [c * q[0] - s * q[1] + 1000.0, s * q[0] + c * q[1] - 500.0];
    let out = p.update(&hs.map(m)).unwrap().to_vec();
    let mut err: f64 = 0.0;
    for (a, b) in out.iter().zip(mesh.vertices()) {
        let e = m(*b);
        err = err.max((a[0] - e[0]).abs()).max((a[1] - e[1]).abs());
    }
    println!("max err {err}");
    assert!(err < 1e-6);
    let out = p.update(&[[0.5, 0.5], [12.0, 3.0], [5.0, 5.5], [2.2, 4.1]]).unwrap();
    println!("{:?}", &out[..3]);
}
