//! The contours of the grown shape ([`super::mesh_image`]'s step 4): the zero level of its
//! field traced by marching squares into closed loops, outer loops counter-clockwise and
//! holes clockwise, clipped exactly at the picture's edges.

use std::collections::HashMap;

/// Traces the zero level of `field` (pixel centres of a `w × h` picture) as closed loops
/// with the positive side on the left in the walk a→b→c→d of each cell, which makes outer
/// loops counter-clockwise in pixel coordinates (positive shoelace area) and holes
/// clockwise. The field is padded by one node on each side with the negated border value,
/// so that loops close and the shape is clipped exactly at the picture's edges. Saddles
/// are resolved by the cell's mean value. O(w·h).
pub(super) fn march(field: &[f32], w: usize, h: usize) -> Vec<Vec<[f64; 2]>> {
    let (nw, nh) = (w + 2, h + 2);
    // The padded value at node (a, b), with a = x + 1, b = y + 1.
    let value = |a: usize, b: usize| -> f32 {
        let v = field[(b.clamp(1, h) - 1) * w + a.clamp(1, w) - 1];
        if a >= 1 && b >= 1 && a <= w && b <= h {
            v
        } else {
            -v.max(0.25)
        }
    };
    // Edge ids: horizontal (a, b)–(a + 1, b) is 2·(b·nw + a), vertical (a, b)–(a, b + 1) is
    // that + 1. Only crossed edges are stored: memory follows the contours' length.
    let mut next: HashMap<u32, u32> = HashMap::new();
    let mut exits: Vec<u32> = Vec::new();
    let mut rows = [vec![0f32; nw], vec![0f32; nw]];
    pad_row(field, w, h, 0, &mut rows[0]);
    for b in 0..nh - 1 {
        let [r0, r1] = &mut rows;
        let (top, bottom) = if b % 2 == 0 { (r0, r1) } else { (r1, r0) };
        pad_row(field, w, h, b + 1, bottom);
        scan_row(top, bottom, b, nw, &mut next, &mut exits);
    }
    let point = |id: u32| -> [f64; 2] {
        let id = id as usize;
        let node = id / 2;
        let (a, b) = (node % nw, node / nw);
        let (a2, b2) = if id % 2 == 0 { (a + 1, b) } else { (a, b + 1) };
        let (p, q) = (value(a, b) as f64, value(a2, b2) as f64);
        let t = p / (p - q);
        // Node (a, b) sits at pixel centre (a − 1 + ½, b − 1 + ½).
        let x0 = a as f64 - 0.5;
        let y0 = b as f64 - 0.5;
        if id % 2 == 0 {
            [x0 + t, y0]
        } else {
            [x0, y0 + t]
        }
    };
    let mut loops = Vec::new();
    for &start in &exits {
        if !next.contains_key(&start) {
            continue;
        }
        let mut l = Vec::new();
        let mut e = start;
        while let Some(n) = next.remove(&e) {
            l.push(point(e));
            e = n;
            if e == start {
                break;
            }
        }
        loops.push(l);
    }
    loops
}

/// Padded row `b` (image row `b − 1`; the padding rows and columns repeat the nearest
/// image value negated, at most −¼).
#[inline(never)]
fn pad_row(field: &[f32], w: usize, h: usize, b: usize, row: &mut [f32]) {
    let y = b.clamp(1, h) - 1;
    let src = &field[y * w..(y + 1) * w];
    if b == 0 || b == h + 1 {
        for (d, &v) in row[1..=w].iter_mut().zip(src) {
            *d = -v.max(0.25);
        }
    } else {
        row[1..=w].copy_from_slice(src);
    }
    row[0] = -src[0].max(0.25);
    row[w + 1] = -src[w - 1].max(0.25);
}

/// The marching-squares cells between padded rows `b` and `b + 1`: links each exit
/// crossing to its entry crossing in `next` and records the exits.
#[inline(never)]
fn scan_row(
    top: &[f32],
    bottom: &[f32],
    b: usize,
    nw: usize,
    next: &mut HashMap<u32, u32>,
    exits: &mut Vec<u32>,
) {
    let hz = |a: usize, b: usize| (2 * (b * nw + a)) as u32;
    let vt = |a: usize, b: usize| (2 * (b * nw + a) + 1) as u32;
    for a in 0..nw - 1 {
        let vals = [top[a], top[a + 1], bottom[a + 1], bottom[a]];
        let inside = vals.map(|v| v > 0.0);
        if inside[0] == inside[1] && inside[1] == inside[2] && inside[2] == inside[3] {
            continue;
        }
        let edges = [hz(a, b), vt(a + 1, b), hz(a, b + 1), vt(a, b)];
        // Exit (inside → outside) and entry crossings along the walk.
        let mut exit = [usize::MAX; 2];
        let mut entry = [usize::MAX; 2];
        let (mut ne, mut nn) = (0, 0);
        for k in 0..4 {
            let (i0, i1) = (inside[k], inside[(k + 1) % 4]);
            if i0 && !i1 {
                exit[ne] = k;
                ne += 1;
            } else if !i0 && i1 {
                entry[nn] = k;
                nn += 1;
            }
        }
        if ne == 1 {
            next.insert(edges[exit[0]], edges[entry[0]]);
            exits.push(edges[exit[0]]);
        } else {
            let centre = vals.iter().sum::<f32>() > 0.0;
            for &x in &exit[..2] {
                // Connected: the next entry after the exit; separate: the previous one.
                let e = if centre {
                    (1..4).map(|d| (x + d) % 4).find(|k| entry.contains(k))
                } else {
                    (1..4).map(|d| (x + 4 - d) % 4).find(|k| entry.contains(k))
                };
                if let Some(e) = e {
                    next.insert(edges[x], edges[e]);
                    exits.push(edges[x]);
                }
            }
        }
    }
}
