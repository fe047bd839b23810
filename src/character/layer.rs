//! [`Layer`]: one layer of a layered picture as the readers give it (`bunraku/psd`,
//! `bunraku/layers`): a name, its groups, a rectangle in canvas pixels, visibility,
//! opacity, a blend mode and its straight RGBA pixels; and the checks a list of layers
//! passes before any work.

use crate::error::{Error, Result};
use crate::limits::{size_allowed, MAX_PIXELS, MAX_SIDE};

/// The most layers a character may have (a PSD character rarely has more than a hundred).
pub const MAX_LAYERS: usize = 4096;

/// The most pixels all layers may have together: four times [`MAX_PIXELS`] (1 GB of RGBA).
pub const MAX_TOTAL_PIXELS: u64 = 4 * MAX_PIXELS;

/// The largest magnitude of a layer rectangle's coordinate, in canvas pixels.
pub const MAX_OFFSET: i64 = 1 << 20;

/// The longest layer name or group path, in UTF-16 units as JS counts them.
pub const MAX_NAME: usize = 1024;

/// How a part is composited over what is beneath it. Other modes are refused: a reader
/// warns about a mode it cannot map and gives `Normal` instead, so that nothing is drawn
/// as normal without a word.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BlendMode {
    /// Source over.
    #[default]
    Normal,
    /// `result = source × destination` (Photoshop's Multiply).
    Multiply,
    /// `result = 1 − (1 − source)(1 − destination)` (Screen).
    Screen,
    /// `result = source + destination`, clamped (Linear Dodge (Add)).
    Additive,
}

impl BlendMode {
    /// Every mode, as the layers and the document name them.
    pub const ALL: [BlendMode; 4] =
        [BlendMode::Normal, BlendMode::Multiply, BlendMode::Screen, BlendMode::Additive];

    /// The mode's name: `"normal"`, `"multiply"`, `"screen"` or `"additive"`.
    pub fn name(self) -> &'static str {
        match self {
            BlendMode::Normal => "normal",
            BlendMode::Multiply => "multiply",
            BlendMode::Screen => "screen",
            BlendMode::Additive => "additive",
        }
    }

    /// The mode named `name`.
    pub fn from_name(name: &str) -> Option<BlendMode> {
        BlendMode::ALL.into_iter().find(|m| m.name() == name)
    }
}

/// One layer: straight (not premultiplied) RGBA pixels over the rectangle `rect =
/// [left, top, right, bottom]` of the canvas (right and bottom exclusive; it may reach past
/// the canvas on any side).
#[derive(Debug, Clone, PartialEq)]
pub struct Layer {
    /// The layer's name (not unique: parts are told apart by index).
    pub name: String,
    /// The slash-separated path of its enclosing groups, `""` at the top level.
    pub group: String,
    /// `[left, top, right, bottom]` in canvas pixels.
    pub rect: [i64; 4],
    /// Whether it is shown: its own flag and every enclosing group's.
    pub visible: bool,
    /// 0 to 1.
    pub opacity: f64,
    /// How it is composited.
    pub blend_mode: BlendMode,
    /// `(right − left) × (bottom − top) × 4` bytes, rows top first.
    pub rgba: Vec<u8>,
}

impl Layer {
    /// The rectangle's width and height.
    pub fn size(&self) -> (u32, u32) {
        let [l, t, r, b] = self.rect;
        ((r - l).clamp(0, u32::MAX as i64) as u32, (b - t).clamp(0, u32::MAX as i64) as u32)
    }

    /// The alpha of canvas pixel `(x, y)`, 0 outside the rectangle.
    pub fn alpha_at(&self, x: i64, y: i64) -> u8 {
        let [l, t, r, b] = self.rect;
        if x < l || y < t || x >= r || y >= b {
            return 0;
        }
        let w = (r - l) as usize;
        self.rgba[((y - t) as usize * w + (x - l) as usize) * 4 + 3]
    }
}

/// Checks a list of layers before any work: its length, each layer's rectangle, pixels,
/// opacity and name, and the pixels of all together.
///
/// Errors: [`Error::TooMany`] (more than [`MAX_LAYERS`]), [`Error::EmptyMesh`] (no layer),
/// [`Error::BadLayer`] naming the layer and field (code `"too-large"` past a limit).
pub fn check_layers(layers: &[Layer]) -> Result<()> {
    if layers.len() > MAX_LAYERS {
        let count = layers.len() as f64;
        return Err(Error::TooMany { what: "layers", count, estimated: false, limit: MAX_LAYERS });
    }
    if layers.is_empty() {
        return Err(Error::EmptyMesh);
    }
    let mut total = 0u64;
    for (index, layer) in layers.iter().enumerate() {
        let bad = |field, reason: String| Error::BadLayer { index, field, reason, too_large: false };
        let large = |field, reason: String| Error::BadLayer { index, field, reason, too_large: true };
        let (w, h) = check_rect(index, layer.rect)?;
        let expected = w as usize * h as usize * 4;
        if layer.rgba.len() != expected {
            return Err(bad(
                "rgba",
                format!("has {} bytes, but the rectangle's {w} × {h} × 4 = {expected}", layer.rgba.len()),
            ));
        }
        total += w as u64 * h as u64;
        if total > MAX_TOTAL_PIXELS {
            return Err(large("rgba", format!("takes the layers past {MAX_TOTAL_PIXELS} pixels in all")));
        }
        if !(0.0..=1.0).contains(&layer.opacity) {
            return Err(bad("opacity", format!("{} is not a number from 0 to 1", layer.opacity)));
        }
        for (field, text) in [("name", &layer.name), ("group", &layer.group)] {
            if text.encode_utf16().count() > MAX_NAME {
                return Err(large(field, format!("is longer than {MAX_NAME} characters")));
            }
        }
    }
    Ok(())
}

/// Checks layer `index`'s rectangle: not empty, within [`MAX_OFFSET`], its size within
/// [`MAX_SIDE`] and [`MAX_PIXELS`]. Returns its width and height. Errors:
/// [`Error::BadLayer`] (code `"too-large"` past a limit).
pub fn check_rect(index: usize, rect: [i64; 4]) -> Result<(u32, u32)> {
    let error = |reason: String, too_large| Error::BadLayer { index, field: "rect", reason, too_large };
    let [l, t, r, b] = rect;
    if rect.iter().any(|c| c.abs() > MAX_OFFSET) {
        return Err(error(format!("[{l}, {t}, {r}, {b}] reaches farther than {MAX_OFFSET} pixels"), true));
    }
    if r <= l || b <= t {
        return Err(error(
            format!("[{l}, {t}, {r}, {b}] is empty: right must exceed left, bottom top"),
            false,
        ));
    }
    let (w, h) = ((r - l) as u32, (b - t) as u32);
    if !size_allowed(w, h) {
        let reason = format!(
            "is {w} × {h} pixels: each side must be at most {MAX_SIDE}, the whole at most {MAX_PIXELS}"
        );
        return Err(error(reason, true));
    }
    Ok((w, h))
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn layer(rect: [i64; 4]) -> Layer {
        let (w, h) = ((rect[2] - rect[0]) as usize, (rect[3] - rect[1]) as usize);
        Layer {
            name: "a".into(),
            group: String::new(),
            rect,
            visible: true,
            opacity: 1.0,
            blend_mode: BlendMode::Normal,
            rgba: vec![255; w * h * 4],
        }
    }

    #[test]
    fn good_layers_pass_and_bad_ones_are_named() {
        assert!(check_layers(&[layer([-5, -5, 10, 10])]).is_ok());
        assert!(matches!(check_layers(&[]), Err(Error::EmptyMesh)));
        let mut empty = layer([0, 0, 4, 4]);
        empty.rect = [0, 0, 0, 4];
        let e = check_layers(&[layer([0, 0, 2, 2]), empty]).unwrap_err();
        assert_eq!(e.code(), "bad-layer");
        assert!(e.to_string().starts_with("layers[1].rect"), "{e}");
        let mut short = layer([0, 0, 4, 4]);
        short.rgba.pop();
        assert!(check_layers(&[short]).unwrap_err().to_string().contains("63 bytes"));
        let mut far = layer([0, 0, 4, 4]);
        far.rect = [0, 0, 4, 1 << 30];
        assert_eq!(check_layers(&[far]).unwrap_err().code(), "too-large");
        let mut dim = layer([0, 0, 1, 1]);
        dim.opacity = f64::NAN;
        assert_eq!(check_layers(&[dim]).unwrap_err().code(), "bad-layer");
    }

    #[test]
    fn blend_modes_read_back_by_name() {
        for m in BlendMode::ALL {
            assert_eq!(BlendMode::from_name(m.name()), Some(m));
        }
        assert_eq!(BlendMode::from_name("overlay"), None);
    }

    #[test]
    fn alpha_is_read_in_canvas_pixels() {
        let mut l = layer([10, 20, 12, 22]);
        l.rgba[7] = 7; // pixel (11, 20): row 0, column 1, alpha
        assert_eq!(l.alpha_at(11, 20), 7);
        assert_eq!(l.alpha_at(10, 20), 255);
        assert_eq!(l.alpha_at(9, 20), 0);
        assert_eq!(l.alpha_at(12, 21), 0);
    }
}
