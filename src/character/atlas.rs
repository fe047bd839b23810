//! The atlas: every part's pixels packed into one texture (research notes, `layers.md`
//! §2.1), so that a character draws from one texture in one pass per blend mode.
//!
//! * **Shelves**: regions sorted by height, tallest first, placed left to right in rows
//!   (shelves) of a width chosen so that the atlas comes out about square; simple, and
//!   within 10–20 % of the best packing for rectangles of similar heights.
//! * **Padding**: each region has [`PADDING`] texels on every side, filled by extending its
//!   edge texels outwards, so that bilinear filtering at a region's edge reads only the
//!   region's own colours, and mipmap levels up to [`MIPMAP_LEVELS`] (a texel of level `k`
//!   averages `2^k × 2^k` texels of level 0) do not reach a neighbour: regions start on
//!   multiples of `2^MIPMAP_LEVELS` texels and are padded to such multiples.
//! * **Straight alpha, premultiplied-safe**: the colour of every transparent texel is that
//!   of its nearest opaque neighbour (dilated a few texels), so filtering straight alpha
//!   does not drag black into the edges, and premultiplying before or after filtering gives
//!   the same edges.

use crate::error::{Error, Result};
use crate::limits::MAX_SIDE;

use super::layer::Layer;

/// Texels of padding around each region, at least (regions are also aligned, see
/// [`MIPMAP_LEVELS`]).
pub const PADDING: u32 = 4;

/// The mipmap levels that never mix two regions: regions sit on a grid of `2^3 = 8`
/// texels. A renderer that mipmaps the atlas should stop at this level
/// (`TEXTURE_MAX_LEVEL`).
pub const MIPMAP_LEVELS: u32 = 3;

/// How far transparent texels take the colour of their nearest opaque neighbour, in texels.
const DILATION: usize = 4;

/// Every part's pixels in one straight-RGBA texture.
#[derive(Debug, Clone, PartialEq)]
pub struct Atlas {
    /// `width × height × 4` bytes, rows top first.
    pub data: Vec<u8>,
    /// In texels.
    pub width: u32,
    /// In texels.
    pub height: u32,
    /// Each layer's region `[x, y, width, height]` (its rectangle's pixels, without the
    /// padding), in the order of the layers given.
    pub regions: Vec<[u32; 4]>,
}

impl Atlas {
    /// Packs the layers' pixels. Errors: [`Error::TooMany`] (code `"too-large"`) when they do not fit in
    /// [`MAX_SIDE`] × [`MAX_SIDE`] texels.
    pub fn pack(layers: &[&Layer]) -> Result<Atlas> {
        let grid = 1u32 << MIPMAP_LEVELS;
        let align = |v: u32| v.div_ceil(grid) * grid;
        // Each region's padded footprint, on the grid.
        let boxes: Vec<(u32, u32)> = layers
            .iter()
            .map(|l| {
                let (w, h) = l.size();
                (align(w + 2 * PADDING), align(h + 2 * PADDING))
            })
            .collect();
        let area: u64 = boxes.iter().map(|&(w, h)| w as u64 * h as u64).sum();
        let widest = boxes.iter().map(|b| b.0).max().unwrap_or(grid);
        let mut order: Vec<usize> = (0..layers.len()).collect();
        order.sort_by_key(|&k| (std::cmp::Reverse(boxes[k].1), k));
        let width = ((area as f64).sqrt().ceil() as u32).max(widest);
        let width = align(width).min(MAX_SIDE.max(widest));
        let (mut x, mut y, mut shelf) = (0u32, 0u32, 0u32);
        let mut corner = vec![(0u32, 0u32); layers.len()];
        for &k in &order {
            let (w, h) = boxes[k];
            if x + w > width {
                x = 0;
                y += shelf;
                shelf = 0;
            }
            corner[k] = (x, y);
            x += w;
            shelf = shelf.max(h);
        }
        let height = y + shelf;
        if width > MAX_SIDE || height > MAX_SIDE {
            return Err(Error::TooMany {
                what: "texels on the atlas's longer side",
                count: width.max(height) as f64,
                estimated: true,
                limit: MAX_SIDE as usize,
            });
        }
        let mut data = vec![0u8; width as usize * height as usize * 4];
        let mut regions = Vec::with_capacity(layers.len());
        for ((layer, &(cx, cy)), &(bw, bh)) in layers.iter().zip(&corner).zip(&boxes) {
            let (w, h) = layer.size();
            let (x0, y0) = (cx + PADDING, cy + PADDING);
            // The padded, aligned box: every texel takes the colour of the nearest texel of
            // the region (the region itself, then its edges extended outwards).
            let mut pixels = dilated(&layer.rgba, w as usize, h as usize);
            for by in 0..bh {
                let sy = by.saturating_sub(PADDING).min(h - 1) as usize;
                for bx in 0..bw {
                    let sx = bx.saturating_sub(PADDING).min(w - 1) as usize;
                    let src = (sy * w as usize + sx) * 4;
                    let dst = ((cy + by) as usize * width as usize + (cx + bx) as usize) * 4;
                    data[dst..dst + 4].copy_from_slice(&pixels[src..src + 4]);
                    // Outside the region itself, only the colour: alpha 0.
                    let inside = bx >= PADDING && by >= PADDING && bx < PADDING + w && by < PADDING + h;
                    if !inside {
                        data[dst + 3] = 0;
                    }
                }
            }
            pixels.clear();
            regions.push([x0, y0, w, h]);
        }
        Ok(Atlas { data, width, height, regions })
    }

    /// The alpha of texel `(x, y)` of region `k`, `(x, y)` relative to the region (0
    /// outside it).
    pub fn alpha(&self, k: usize, x: i64, y: i64) -> u8 {
        let [rx, ry, w, h] = self.regions[k];
        if x < 0 || y < 0 || x >= w as i64 || y >= h as i64 {
            return 0;
        }
        self.data[((ry as usize + y as usize) * self.width as usize + rx as usize + x as usize) * 4 + 3]
    }
}

/// `rgba` (straight alpha, `w × h`) with the colour of each transparent texel within
/// [`DILATION`] texels of an opaque one replaced by the mean colour of its 8-neighbours
/// coloured before it (alpha unchanged), ring by ring outwards: filtering then mixes an edge
/// texel only with colours like its own. The first ring is found by one sweep (a 3 × 3 box
/// "any opaque" as a row pass and a column pass); each later ring from the one before, so
/// the cost beyond the sweep follows the outline, not the transparent area (measured: the
/// former whole-picture passes took three quarters of `Character.fromLayers` on a
/// 2048 × 2048 PSD of 20 layers).
fn dilated(rgba: &[u8], w: usize, h: usize) -> Vec<u8> {
    let mut out = rgba.to_vec();
    let mut known: Vec<bool> = rgba.chunks_exact(4).map(|p| p[3] > 0).collect();
    let neighbours = |i: usize| {
        let (x, y) = ((i % w) as i64, (i / w) as i64);
        [(-1i64, -1i64), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)]
            .into_iter()
            .map(move |(dx, dy)| (x + dx, y + dy))
            .filter(|&(nx, ny)| nx >= 0 && ny >= 0 && nx < w as i64 && ny < h as i64)
            .map(|(nx, ny)| ny as usize * w + nx as usize)
    };
    // Ring 1: transparent texels with an opaque texel in their 3 × 3 box.
    let row_any: Vec<bool> = (0..w * h)
        .map(|i| {
            let x = i % w;
            known[i] || (x > 0 && known[i - 1]) || (x + 1 < w && known[i + 1])
        })
        .collect();
    let mut ring: Vec<usize> = (0..w * h)
        .filter(|&i| {
            !known[i] && (row_any[i] || (i >= w && row_any[i - w]) || (i + w < w * h && row_any[i + w]))
        })
        .collect();
    let mut queued = vec![false; if ring.is_empty() { 0 } else { w * h }];
    for &i in &ring {
        queued[i] = true;
    }
    for _ in 0..DILATION {
        if ring.is_empty() {
            break;
        }
        // Every texel of the ring takes the colours known before the ring.
        let colours: Vec<(usize, [u8; 3])> = ring
            .iter()
            .map(|&i| {
                let (mut sum, mut count) = ([0u32; 3], 0u32);
                for k in neighbours(i).filter(|&k| known[k]) {
                    for (c, s) in sum.iter_mut().enumerate() {
                        *s += out[k * 4 + c] as u32;
                    }
                    count += 1;
                }
                (i, sum.map(|s| (s / count.max(1)) as u8))
            })
            .collect();
        for (i, c) in colours {
            out[i * 4..i * 4 + 3].copy_from_slice(&c);
            known[i] = true;
        }
        let mut next = Vec::with_capacity(ring.len() + 8);
        for &i in &ring {
            for k in neighbours(i) {
                if !known[k] && !queued[k] {
                    queued[k] = true;
                    next.push(k);
                }
            }
        }
        ring = next;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::character::layer::BlendMode;

    fn solid(w: i64, h: i64, colour: [u8; 4]) -> Layer {
        let rgba = colour.iter().copied().cycle().take((w * h * 4) as usize).collect();
        Layer {
            name: String::new(),
            group: String::new(),
            rect: [0, 0, w, h],
            visible: true,
            opacity: 1.0,
            blend_mode: BlendMode::Normal,
            rgba,
        }
    }

    #[test]
    fn regions_hold_their_pixels_apart_on_the_grid() {
        let layers = [
            solid(30, 10, [255, 0, 0, 255]),
            solid(7, 40, [0, 255, 0, 255]),
            solid(16, 16, [0, 0, 255, 128]),
        ];
        let refs: Vec<&Layer> = layers.iter().collect();
        let atlas = Atlas::pack(&refs).unwrap();
        let grid = 1 << MIPMAP_LEVELS;
        for (a, (layer, region)) in layers.iter().zip(&atlas.regions).enumerate() {
            let [x, y, w, h] = *region;
            assert_eq!((w, h), layer.size());
            assert_eq!(((x - PADDING) % grid, (y - PADDING) % grid), (0, 0));
            // Every texel of the padded, aligned box carries only this region's colour.
            let (x0, y0) = (x - PADDING, y - PADDING);
            let (x1, y1) = ((x + w + PADDING).div_ceil(grid) * grid, (y + h + PADDING).div_ceil(grid) * grid);
            for ty in y0..y1.min(atlas.height) {
                for tx in x0..x1.min(atlas.width) {
                    let k = ((ty * atlas.width + tx) * 4) as usize;
                    let texel = &atlas.data[k..k + 4];
                    let inside = tx >= x && ty >= y && tx < x + w && ty < y + h;
                    if inside {
                        assert_eq!(texel, &layer.rgba[..4], "region {a} at ({tx}, {ty})");
                    } else {
                        assert_eq!(&texel[..3], &layer.rgba[..3], "padding of {a} at ({tx}, {ty})");
                        assert_eq!(texel[3], 0);
                    }
                }
            }
            // No two padded boxes overlap.
            for (b, other) in atlas.regions.iter().enumerate().skip(a + 1) {
                let [ox, oy, ow, oh] = *other;
                let apart = x + w + PADDING <= ox - PADDING
                    || ox + ow + PADDING <= x - PADDING
                    || y + h + PADDING <= oy - PADDING
                    || oy + oh + PADDING <= y - PADDING;
                assert!(apart, "regions {a} and {b} overlap");
            }
        }
        assert_eq!(atlas.alpha(2, 3, 3), 128);
        assert_eq!(atlas.alpha(2, -1, 3), 0);
    }

    /// The dilation as first written: every pass looks at every texel.
    fn reference_dilated(rgba: &[u8], w: usize, h: usize) -> Vec<u8> {
        let mut out = rgba.to_vec();
        let mut known: Vec<bool> = rgba.chunks_exact(4).map(|p| p[3] > 0).collect();
        for _ in 0..DILATION {
            let before = known.clone();
            for y in 0..h {
                for x in 0..w {
                    if before[y * w + x] {
                        continue;
                    }
                    let (mut sum, mut count) = ([0u32; 3], 0u32);
                    for dy in -1i64..=1 {
                        for dx in -1i64..=1 {
                            let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                            if (dx, dy) == (0, 0) || nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                                continue;
                            }
                            let k = ny as usize * w + nx as usize;
                            if before[k] {
                                for c in 0..3 {
                                    sum[c] += out[k * 4 + c] as u32;
                                }
                                count += 1;
                            }
                        }
                    }
                    if count == 0 {
                        continue;
                    }
                    for c in 0..3 {
                        out[(y * w + x) * 4 + c] = (sum[c] / count) as u8;
                    }
                    known[y * w + x] = true;
                }
            }
        }
        out
    }

    #[test]
    fn the_ring_dilation_is_the_whole_picture_one() {
        let mut seed = 7u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 33) as u32
        };
        for (w, h) in [(1, 1), (7, 1), (1, 9), (23, 17), (40, 31)] {
            for density in [0, 1, 5, 50] {
                let rgba: Vec<u8> = (0..w * h)
                    .flat_map(|_| {
                        let opaque = next() % 100 < density;
                        [
                            next() as u8,
                            next() as u8,
                            next() as u8,
                            if opaque { 1 + next() as u8 % 255 } else { 0 },
                        ]
                    })
                    .collect();
                assert_eq!(
                    dilated(&rgba, w, h),
                    reference_dilated(&rgba, w, h),
                    "{w} × {h}, {density} % opaque"
                );
            }
        }
    }

    #[test]
    fn transparent_texels_take_their_neighbours_colour() {
        let mut layer = solid(6, 1, [200, 100, 50, 255]);
        for p in 3..6 {
            layer.rgba[p * 4..p * 4 + 4].copy_from_slice(&[0, 0, 0, 0]);
        }
        let d = dilated(&layer.rgba, 6, 1);
        assert_eq!(&d[3 * 4..3 * 4 + 4], &[200, 100, 50, 0]);
        assert_eq!(&d[5 * 4..5 * 4 + 4], &[200, 100, 50, 0]);
    }
}
