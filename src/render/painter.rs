//! Step 1 of the module docs of [`super`], triangle by triangle: a triangle, or the strip
//! around one of its silhouette edges, textured with the triangle's map from output pixels
//! to texture pixels, into the layer.

use super::raster::{Target, Texture, TextureMap};

/// Half the width of the strip filled around silhouette edges, in output pixels: every
/// pixel that anti-aliasing partly covers has its centre within √2 / 2 of the silhouette.
const FRINGE: f64 = 1.0;

/// What drawing a triangle or a silhouette strip into the layer needs.
pub(super) struct Painter<'a> {
    pub(super) pixels: &'a [[f64; 2]],
    pub(super) triangles: &'a [[u32; 3]],
    pub(super) uvs: &'a [[f32; 2]],
    pub(super) texture: &'a Texture,
}

impl Painter<'_> {
    fn corners(&self, t: usize) -> [[f64; 2]; 3] {
        self.triangles[t].map(|i| self.pixels[i as usize])
    }

    /// Triangle `t`'s map from output pixels to texture pixels.
    fn map(&self, t: usize) -> TextureMap {
        let texture = self.texture;
        let tex = self.triangles[t].map(|i| {
            let uv = self.uvs[i as usize];
            [uv[0] as f64 * texture.width as f64, uv[1] as f64 * texture.height as f64]
        });
        TextureMap::new(self.corners(t), tex)
    }

    /// Triangle `t`, textured.
    pub(super) fn triangle(&self, target: &mut Target, t: usize) {
        target.fill(&self.corners(t), &self.map(t), self.texture);
    }

    /// The strip `FRINGE` pixels either side of triangle `t`'s local edge `k` (and beyond its
    /// ends), textured with the triangle's map extended.
    pub(super) fn strip(&self, target: &mut Target, t: u32, k: u8) {
        let (t, k) = (t as usize, k as usize);
        let c = self.corners(t);
        let (a, b) = (c[k], c[(k + 1) % 3]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        if len <= 1e-9 {
            return;
        }
        let (ex, ey) = (dx / len * FRINGE, dy / len * FRINGE);
        let quad = [
            [a[0] - ex + ey, a[1] - ey - ex],
            [b[0] + ex + ey, b[1] + ey - ex],
            [b[0] + ex - ey, b[1] + ey + ex],
            [a[0] - ex - ey, a[1] - ey + ex],
        ];
        target.fill(&quad, &self.map(t), self.texture);
    }
}
