//! `Renderer`: the core's headless renderer (src/render.rs) behind a JS class. Its buffers
//! live in the object, so that a frame of the same size as the last allocates nothing.

use js_sys::{Float32Array, Float64Array, Uint32Array, Uint8Array, Uint8ClampedArray};
use wasm_bindgen::prelude::*;

use super::errors::bad_type;
use super::options::{render_options, RenderBuffers};
use super::{pixels, read_items, rgba_bytes, typed, Thrown};
use crate::render::Renderer;
use crate::Error;

/// Draws a textured, deformed mesh into RGBA pixels, headless (no canvas, no GPU): for
/// tests, for writing frames from Node, and as a Canvas 2D fallback.
///
/// ```js
/// const renderer = new Renderer(imageData.data, imageData.width, imageData.height);
/// const frame = new Uint8ClampedArray(800 * 600 * 4);
/// renderer.renderInto(frame, puppet.update(targets), mesh.triangles, mesh.uvs, 800, 600,
///                     { transform: [1, 0, 0, 1, 100, 0], background: [255, 255, 255, 255] });
/// ctx.putImageData(new ImageData(frame, 800, 600), 0, 0);
/// renderer.free();
/// ```
#[wasm_bindgen(js_name = Renderer)]
pub struct JsRenderer {
    core: Renderer,
    positions: Vec<[f64; 2]>,
    triangles: Vec<[u32; 3]>,
    uvs: Vec<[f32; 2]>,
    frame: Vec<u8>,
    options: RenderBuffers,
}

#[wasm_bindgen(js_class = Renderer)]
impl JsRenderer {
    /// Takes the texture: `rgba` (a `Uint8Array` or `Uint8ClampedArray`, e.g.
    /// `ImageData.data`) holds `width × height` pixels of 4 bytes, straight (not
    /// premultiplied) RGBA, row by row from the top. Throws on a buffer whose length is not
    /// `width × height × 4`, or a side of 0 or above 16384 (or more than 2²⁶ pixels).
    #[wasm_bindgen(constructor)]
    pub fn new(
        #[wasm_bindgen(unchecked_param_type = "Uint8Array | Uint8ClampedArray")] rgba: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] width: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] height: JsValue,
    ) -> Result<JsRenderer, Thrown> {
        let (width, height) = (pixels("width", &width)?, pixels("height", &height)?);
        let core = Renderer::from_vec(rgba_bytes(&rgba)?, width, height)?;
        Ok(JsRenderer {
            core,
            positions: Vec::new(),
            triangles: Vec::new(),
            uvs: Vec::new(),
            frame: Vec::new(),
            options: RenderBuffers::default(),
        })
    }

    /// Renders a `width × height` frame and returns it as a new `Uint8ClampedArray` of
    /// straight RGBA, ready for `new ImageData(pixels, width, height)`.
    ///
    /// `positions` (`Float64Array`, `[x0, y0, …]`, e.g. what `Puppet.update` returns),
    /// `triangles` (`Uint32Array`, `[a, b, c, …]`) and `uvs` (`Float32Array`, `[u0, v0, …]`
    /// in 0..1 with v down, one pair per vertex, e.g. `Mesh.uvs`) describe the mesh; a uv
    /// `(u, v)` is the texture point `(u · width, v · height)` in pixels. Flipped triangles
    /// are drawn; where triangles overlap the later one shows (with
    /// `options.depth`, the deeper one, its edge anti-aliased); the silhouette is
    /// anti-aliased and shared edges leave no seams. Throws a `BunrakuError` naming the
    /// offending item: wrong array types or lengths, a triangle naming a missing vertex, a
    /// non-finite value, an unknown or bad option, a frame side of 0 or above 16384.
    // A fresh array over its own `ArrayBuffer`, as `new ImageData(…)` wants it.
    #[wasm_bindgen(unchecked_return_type = "Uint8ClampedArray<ArrayBuffer>")]
    pub fn render(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] positions: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Uint32Array")] triangles: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float32Array")] uvs: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] width: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] height: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "RenderOptions")] options: JsValue,
    ) -> Result<JsValue, Thrown> {
        let (width, height) = (pixels("width", &width)?, pixels("height", &height)?);
        self.draw(&positions, &triangles, &uvs, width, height, &options)?;
        Ok(Uint8ClampedArray::from(&self.frame[..]).into())
    }

    /// Like `render`, but writes the frame into `out` (a `Uint8ClampedArray` or
    /// `Uint8Array` of `width × height × 4` bytes, e.g. `ImageData.data`): no output is
    /// allocated, and with the same frame size and triangles as the previous call, nothing
    /// else but what the anti-aliased outline fill needs. The call for every animation
    /// frame.
    #[wasm_bindgen(js_name = renderInto)]
    #[allow(clippy::too_many_arguments)]
    pub fn render_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Uint8ClampedArray | Uint8Array")] out: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] positions: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Uint32Array")] triangles: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float32Array")] uvs: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] width: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] height: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "RenderOptions")] options: JsValue,
    ) -> Result<(), Thrown> {
        let (width, height) = (pixels("width", &width)?, pixels("height", &height)?);
        let expected = width as u64 * height as u64 * 4;
        let (got, clamped) = if let Some(a) = out.dyn_ref::<Uint8ClampedArray>() {
            (a.length(), Some(a))
        } else if let Some(a) = out.dyn_ref::<Uint8Array>() {
            (a.length(), None)
        } else {
            return Err(bad_type("out", "a Uint8ClampedArray or a Uint8Array", &out));
        };
        if got as u64 != expected {
            // The frame size is checked first: a bad one is the better message.
            Renderer::check_frame_size(width, height)?;
            let (got, expected) = (got as usize, expected as usize);
            return Err(Error::CountMismatch { what: "output length", got, expected }.into());
        }
        self.draw(&positions, &triangles, &uvs, width, height, &options)?;
        match clamped {
            Some(a) => a.copy_from(&self.frame),
            None => out.unchecked_ref::<Uint8Array>().copy_from(&self.frame),
        }
        Ok(())
    }

    /// Reads the mesh and the options into the renderer's buffers and draws the frame into
    /// `self.frame`.
    fn draw(
        &mut self,
        positions: &JsValue,
        triangles: &JsValue,
        uvs: &JsValue,
        width: u32,
        height: u32,
        options: &JsValue,
    ) -> Result<(), Thrown> {
        read_items("positions", typed::<Float64Array>("positions", positions)?, &mut self.positions)?;
        read_items("triangles", typed::<Uint32Array>("triangles", triangles)?, &mut self.triangles)?;
        let uvs = typed::<Float32Array>("uvs", uvs)?;
        // Checked here, not only by the core, to give the lengths of the arrays passed.
        let (got, expected) = (uvs.length() as usize, 2 * self.positions.len());
        if got != expected {
            return Err(Error::CountMismatch { what: "uvs", got, expected }.into());
        }
        read_items("uvs", uvs, &mut self.uvs)?;
        Renderer::check_frame_size(width, height)?;
        // The options borrow the renderer's buffers (so that reading them allocates
        // nothing), which the frame gives back whether it is drawn or not.
        let options = render_options(options, &mut self.options)?;
        self.frame.resize(width as usize * height as usize * 4, 0);
        let (positions, triangles, uvs) = (&self.positions, &self.triangles, &self.uvs);
        let drawn =
            self.core.render_into(&mut self.frame, positions, triangles, uvs, width, height, &options);
        self.options.restore(options);
        Ok(drawn?)
    }

    /// The texture's width, in pixels.
    #[wasm_bindgen(getter)]
    pub fn width(&self) -> u32 {
        self.core.width()
    }

    /// The texture's height, in pixels.
    #[wasm_bindgen(getter)]
    pub fn height(&self) -> u32 {
        self.core.height()
    }
}
