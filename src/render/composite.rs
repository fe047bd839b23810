//! Step 3: the layer, weighted by the coverage, over the background, demultiplied into the
//! frame.

use super::coverage::{Coverage, Region};
use super::raster::div255;
use super::LevelStyle;
use crate::character::BlendMode;

/// Step 3 of the module docs: `out = demultiply(layer · coverage + background · (1 − α))`,
/// the coverage of each pixel being the running sum of its row's cells; outside `region`,
/// the background.
pub(super) fn composite(
    layer: &[u32],
    coverage: &Coverage,
    region: &Region,
    background: [u8; 4],
    out: &mut [u8],
) {
    let ba = background[3] as u32;
    let bg = [0, 1, 2].map(|k| div255(background[k] as u32 * ba));
    let (width, stride) = (coverage.width, coverage.stride());
    let (x0, x1) = (region.x0, region.x1.min(width));
    let rows = out
        .chunks_exact_mut(4 * width)
        .zip(layer.chunks_exact(width))
        .zip(coverage.cells.chunks_exact(stride));
    for (j, ((out, layer), cells)) in rows.enumerate() {
        if j < region.y0 || j >= region.y1 || x0 >= x1 {
            out.chunks_exact_mut(4).for_each(|o| o.copy_from_slice(&background));
            continue;
        }
        out[..4 * x0].chunks_exact_mut(4).for_each(|o| o.copy_from_slice(&background));
        out[4 * x1..].chunks_exact_mut(4).for_each(|o| o.copy_from_slice(&background));
        let mut sum = 0.0f32;
        let inside = out[4 * x0..4 * x1].chunks_exact_mut(4).zip(&layer[x0..x1]).zip(&cells[x0..x1]);
        for ((o, &l), &cell) in inside {
            sum += cell;
            let m = (sum.abs().min(1.0) * 255.0 + 0.5) as u32;
            let l = l.to_le_bytes();
            if m == 0 || l[3] == 0 {
                o.copy_from_slice(&background);
                continue;
            }
            if m == 255 && l[3] == 255 {
                o.copy_from_slice(&l);
                continue;
            }
            let sa = div255(l[3] as u32 * m);
            let inv = 255 - sa;
            let a = sa + div255(ba * inv);
            if a == 0 {
                o.copy_from_slice(&[0; 4]);
                continue;
            }
            for k in 0..3 {
                let c = div255(l[k] as u32 * m) + div255(bg[k] * inv);
                o[k] = ((c * 255 + a / 2) / a).min(255) as u8;
            }
            o[3] = a as u8;
        }
    }
}

/// The premultiplied colour `s` blended over `d` by `mode` ([`LevelStyle::blend`]), each
/// channel in 0–255, alpha by the same formula as the colours (normal and screen:
/// `αs + αd − αs·αd`; multiply: `αd`, so it leaves nothing over transparency; additive:
/// `αs + αd`, clamped).
fn blend(mode: BlendMode, s: [u32; 4], d: [u8; 4]) -> [u8; 4] {
    let d = d.map(u32::from);
    let over = |k: usize| s[k] + div255(d[k] * (255 - s[3]));
    let c = |k: usize| match mode {
        BlendMode::Normal => over(k),
        // WebGL's blendFunc(DST_COLOR, ONE_MINUS_SRC_ALPHA), alpha included: αs·αd + αd(1 − αs).
        BlendMode::Multiply => div255(s[k] * d[k]) + div255(d[k] * (255 - s[3])),
        BlendMode::Screen => s[k] + d[k] - div255(s[k] * d[k]),
        BlendMode::Additive => s[k] + d[k],
    };
    [0, 1, 2, 3].map(|k| c(k).min(255) as u8)
}

/// The background premultiplied, as the layered frame holds it.
pub(super) fn premultiplied(background: [u8; 4]) -> u32 {
    let a = background[3] as u32;
    let c = |k: usize| div255(background[k] as u32 * a) as u8;
    u32::from_le_bytes([c(0), c(1), c(2), background[3]])
}

/// One depth level over the frame so far (premultiplied, one `u32` a pixel, like the
/// layer): `frame = layer · coverage + frame · (1 − α)` over `own` (the level's part of the
/// frame: elsewhere its layer is empty), the coverage of each pixel being the running sum
/// of its row's cells from `from_x` (where the level's coverage path starts).
pub(super) fn composite_over(
    layer: &[u32],
    coverage: &Coverage,
    own: &Region,
    from_x: usize,
    style: LevelStyle,
    frame: &mut [u32],
) {
    let opacity = style.opacity.clamp(0.0, 1.0);
    let (width, stride) = (coverage.width, coverage.stride());
    let (x0, x1) = (own.x0, own.x1.min(width));
    if x0 >= x1 {
        return;
    }
    let from_x = from_x.min(x0);
    for j in own.y0..own.y1 {
        let cells = &coverage.cells[j * stride..(j + 1) * stride];
        let mut sum = 0.0f32;
        for &cell in &cells[from_x..x0] {
            sum += cell;
        }
        let row = j * width;
        let pixels = frame[row + x0..row + x1].iter_mut().zip(&layer[row + x0..row + x1]).zip(&cells[x0..x1]);
        for ((f, &l), &cell) in pixels {
            sum += cell;
            if l == 0 {
                continue;
            }
            let m = (sum.abs().min(1.0) * opacity * 255.0 + 0.5) as u32;
            let l = l.to_le_bytes();
            if m == 255 && l[3] == 255 && style.blend == BlendMode::Normal {
                *f = u32::from_le_bytes(l);
                continue;
            }
            *f = u32::from_le_bytes(blend(style.blend, l.map(|x| div255(x as u32 * m)), f.to_le_bytes()));
        }
    }
}

/// The layered frame (premultiplied) demultiplied into `out` over `region`, the background
/// elsewhere and wherever the frame still holds just the background.
pub(super) fn demultiply(frame: &[u32], width: usize, region: &Region, background: [u8; 4], out: &mut [u8]) {
    let bg = premultiplied(background);
    let (x0, x1) = (region.x0, region.x1.min(width));
    for (j, (out, frame)) in out.chunks_exact_mut(4 * width).zip(frame.chunks_exact(width)).enumerate() {
        if j < region.y0 || j >= region.y1 || x0 >= x1 {
            out.chunks_exact_mut(4).for_each(|o| o.copy_from_slice(&background));
            continue;
        }
        out[..4 * x0].chunks_exact_mut(4).for_each(|o| o.copy_from_slice(&background));
        out[4 * x1..].chunks_exact_mut(4).for_each(|o| o.copy_from_slice(&background));
        for (o, &p) in out[4 * x0..4 * x1].chunks_exact_mut(4).zip(&frame[x0..x1]) {
            if p == bg {
                o.copy_from_slice(&background);
                continue;
            }
            let p = p.to_le_bytes();
            let a = p[3] as u32;
            if a == 0 {
                o.copy_from_slice(&[0; 4]);
                continue;
            }
            for k in 0..3 {
                o[k] = ((p[k] as u32 * 255 + a / 2) / a).min(255) as u8;
            }
            o[3] = p[3];
        }
    }
}

/// `colour` (straight RGBA) over `out` (straight RGBA), weighted by the coverage over
/// `region` (the running sum of each row's cells): the overlays' paint.
pub(super) fn over_straight(colour: [u8; 4], coverage: &Coverage, region: &Region, out: &mut [u8]) {
    let (width, stride) = (coverage.width, coverage.stride());
    let (x0, x1) = (region.x0, region.x1.min(width));
    let ca = colour[3] as u32;
    if x0 >= x1 || ca == 0 {
        return;
    }
    for j in region.y0..region.y1 {
        let cells = &coverage.cells[j * stride + x0..j * stride + x1];
        let row = &mut out[4 * (j * width + x0)..4 * (j * width + x1)];
        let mut sum = 0.0f32;
        for (o, &cell) in row.chunks_exact_mut(4).zip(cells) {
            sum += cell;
            let m = (sum.abs().min(1.0) * 255.0 + 0.5) as u32;
            let sa = div255(ca * m);
            if sa == 0 {
                continue;
            }
            let (da, inv) = (o[3] as u32, 255 - sa);
            if da == 255 {
                // Over an opaque pixel (a frame with a background, or inside the mesh): no
                // division.
                for k in 0..3 {
                    o[k] = div255(colour[k] as u32 * sa + o[k] as u32 * inv) as u8;
                }
                continue;
            }
            // In units of 1/255²: source sa · colour, destination da · (255 − sa) · out.
            let a = sa * 255 + da * inv;
            for k in 0..3 {
                let c = colour[k] as u32 * sa * 255 + o[k] as u32 * da * inv;
                o[k] = ((c + a / 2) / a).min(255) as u8;
            }
            o[3] = ((a + 127) / 255) as u8;
        }
    }
}
