//! Step 1's scan conversion: the texture (premultiplied), the affine map of a triangle from
//! output pixels to texture pixels, and the watertight fill of a convex polygon into the
//! layer, every covered pixel centre sampled bilinearly.

/// The texture, premultiplied RGBA, one `u32` per pixel (`u32::from_le_bytes([r, g, b, a])`).
#[derive(Debug)]
pub(super) struct Texture {
    pub(super) texels: Vec<u32>,
    pub(super) width: u32,
    pub(super) height: u32,
}

/// The affine map from output pixels to texture pixels of one triangle.
pub(super) struct TextureMap {
    /// `texture = m · (x, y) + o`.
    m: [[f64; 2]; 2],
    o: [f64; 2],
}

impl TextureMap {
    /// The map sending the output-pixel corners `p` to the texture-pixel corners `t`
    /// (`p` must have an area; `t` need not).
    pub(super) fn new(p: [[f64; 2]; 3], t: [[f64; 2]; 3]) -> TextureMap {
        let (p1, p2) = ([p[1][0] - p[0][0], p[1][1] - p[0][1]], [p[2][0] - p[0][0], p[2][1] - p[0][1]]);
        let (t1, t2) = ([t[1][0] - t[0][0], t[1][1] - t[0][1]], [t[2][0] - t[0][0], t[2][1] - t[0][1]]);
        let det = p1[0] * p2[1] - p2[0] * p1[1];
        // M = T P⁻¹ with P = [p1 p2], T = [t1 t2] (columns).
        let inv = [[p2[1] / det, -p2[0] / det], [-p1[1] / det, p1[0] / det]];
        let m = [
            [t1[0] * inv[0][0] + t2[0] * inv[1][0], t1[0] * inv[0][1] + t2[0] * inv[1][1]],
            [t1[1] * inv[0][0] + t2[1] * inv[1][0], t1[1] * inv[0][1] + t2[1] * inv[1][1]],
        ];
        let o = [
            t[0][0] - m[0][0] * p[0][0] - m[0][1] * p[0][1],
            t[0][1] - m[1][0] * p[0][0] - m[1][1] * p[0][1],
        ];
        TextureMap { m, o }
    }
}

/// The layer being drawn: `width × height` premultiplied texels.
pub(super) struct Target<'a> {
    pub(super) texels: &'a mut [u32],
    pub(super) width: usize,
    pub(super) height: usize,
}

impl Target<'_> {
    /// Fills the convex polygon `polygon` (output pixels, either orientation, at most 4
    /// corners): every pixel whose centre `(i + ½, j + ½)` lies inside gets the texture
    /// sampled at `map` of that centre. A centre exactly on an edge is inside when the edge
    /// bounds the polygon on the centre's right; on a row through a vertex, the edges below
    /// it count: so neighbours sharing an edge never both take a pixel and never both miss
    /// one.
    #[inline(never)]
    pub(super) fn fill(&mut self, polygon: &[[f64; 2]], map: &TextureMap, texture: &Texture) {
        let n = polygon.len().min(4);
        // Each edge from its upper end (smaller y; then smaller x) to its lower end, so that
        // the two triangles of a shared edge compute the same crossings bit for bit.
        let mut edges = [(0.0, 0.0, 0.0, 0.0); 4];
        let (mut y_min, mut y_max) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..n {
            let (p, q) = (polygon[k], polygon[(k + 1) % n]);
            let (p, q) = if (p[1], p[0]) <= (q[1], q[0]) { (p, q) } else { (q, p) };
            edges[k] = (p[1], q[1], p[0], (q[0] - p[0]) / (q[1] - p[1]));
            y_min = y_min.min(p[1]);
            y_max = y_max.max(q[1]);
        }
        // Rows whose centre y satisfies y_min ≤ y < y_max.
        let (j0, j1) = (ceil_within(y_min - 0.5, self.height), ceil_within(y_max - 0.5, self.height));
        for j in j0..j1 {
            let yc = j as f64 + 0.5;
            let (mut x_left, mut x_right) = (f64::INFINITY, f64::NEG_INFINITY);
            for &(top, bottom, x_top, slope) in &edges[..n] {
                if top <= yc && yc < bottom {
                    let x = x_top + (yc - top) * slope;
                    x_left = x_left.min(x);
                    x_right = x_right.max(x);
                }
            }
            // Columns whose centre x satisfies x_left ≤ x < x_right.
            let (i0, i1) = (ceil_within(x_left - 0.5, self.width), ceil_within(x_right - 0.5, self.width));
            if i0 >= i1 {
                continue;
            }
            let [[a, b], [c, d]] = map.m;
            let x0 = i0 as f64 + 0.5;
            let (mut s, mut t) = (a * x0 + b * yc + map.o[0], c * x0 + d * yc + map.o[1]);
            for out in &mut self.texels[j * self.width + i0..j * self.width + i1] {
                *out = texture.bilinear(s, t);
                s += a;
                t += c;
            }
        }
    }
}

impl Texture {
    /// The premultiplied colour at texture point `(s, t)` (pixel `(i, j)` covers
    /// `[i, i + 1] × [j, j + 1]`): bilinear between the four nearest pixel centres, the edge
    /// pixels repeated beyond the texture (pad), with 8-bit weights.
    pub(super) fn bilinear(&self, s: f64, t: f64) -> u32 {
        // In 1/256 texel, from the pixel centres (−½) and rounded; clamped first (a NaN
        // becomes the lower bound) to just beyond the texture, which pads the same, and
        // shifted to positive values, so that truncation is floor.
        let fixed = |v: f64, n: u32| ((v.max(-2.0).min(n as f64 + 2.0) + 3.5) * 256.0 + 0.5) as i32 - 4 * 256;
        let (x, y) = (fixed(s, self.width), fixed(t, self.height));
        let (x0, y0) = (x >> 8, y >> 8);
        let (wx, wy) = ((x & 255) as u32, (y & 255) as u32);
        let (w, h) = (self.width as i32, self.height as i32);
        let (xa, xb) = (x0.clamp(0, w - 1) as usize, (x0 + 1).clamp(0, w - 1) as usize);
        let (ya, yb) =
            (y0.clamp(0, h - 1) as usize * w as usize, (y0 + 1).clamp(0, h - 1) as usize * w as usize);
        let texel = |k: usize| self.texels.get(k).copied().unwrap_or(0);
        let (c00, c10, c01, c11) = (texel(ya + xa), texel(ya + xb), texel(yb + xa), texel(yb + xb));
        // Two channels at a time, 8-bit weights in 0..=255.
        const M: u32 = 0x00ff_00ff;
        let lerp = |a: u32, b: u32, w: u32| ((a * (256 - w) + b * w + 0x0080_0080) >> 8) & M;
        let rb = lerp(lerp(c00 & M, c10 & M, wx), lerp(c01 & M, c11 & M, wx), wy);
        let ga = lerp(lerp(c00 >> 8 & M, c10 >> 8 & M, wx), lerp(c01 >> 8 & M, c11 >> 8 & M, wx), wy);
        rb | ga << 8
    }
}

/// `⌈x⌉` clamped to `0..=limit` (NaN gives 0), without a call to libm's `ceil`.
pub(super) fn ceil_within(x: f64, limit: usize) -> usize {
    if x.is_nan() || x <= 0.0 {
        return 0;
    }
    if x >= limit as f64 {
        return limit;
    }
    let t = x as usize;
    if (t as f64) < x {
        t + 1
    } else {
        t
    }
}

/// `x / 255`, rounded, for `x ≤ 255 · 255`.
pub(super) fn div255(x: u32) -> u32 {
    let x = x + 128;
    (x + (x >> 8)) >> 8
}
