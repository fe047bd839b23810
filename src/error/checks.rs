//! The checks of input numbers that many entry points share, with the errors they name:
//! non-finite and too-large coordinates, flat coordinate arrays, and the count of poses as
//! [`Error::BadPose`] words it.

use super::{Error, Result};

/// Checks that every coordinate of `points` is finite, naming the first bad item.
pub(crate) fn check_finite<T: Copy + Into<f64>, const D: usize>(
    what: &'static str,
    points: &[[T; D]],
) -> Result<()> {
    for (index, p) in points.iter().enumerate() {
        for (c, &value) in p.iter().enumerate() {
            let value: f64 = value.into();
            if !value.is_finite() {
                return Err(Error::NonFinite { what, index, flat: D * index + c, value });
            }
        }
    }
    Ok(())
}

/// Checks that every coordinate of `points` is finite ([`Error::NonFinite`]) and within
/// ±[`crate::limits::MAX_COORDINATE`] ([`Error::TooLarge`]), naming the first that is not.
pub(crate) fn check_coordinates(what: &'static str, points: &[[f64; 2]]) -> Result<()> {
    check_finite(what, points)?;
    let limit = crate::limits::MAX_COORDINATE;
    for (index, p) in points.iter().enumerate() {
        if let Some(c) = (0..2).find(|&c| p[c].abs() > limit) {
            return Err(Error::TooLarge { what, index, flat: 2 * index + c, value: p[c], limit });
        }
    }
    Ok(())
}

/// How many poses a blender has, as [`Error::BadPose`] says it: `there are no poses`,
/// `there is 1 pose`, `there are 3 poses`.
pub(crate) fn there_are_poses(count: usize) -> String {
    match count {
        0 => "there are no poses".into(),
        1 => "there is 1 pose".into(),
        n => format!("there are {n} poses"),
    }
}

/// Reinterprets a flat `[x0, y0, x1, y1, …]` slice as points, checking its length.
pub fn points_from_flat(what: &'static str, flat: &[f64]) -> Result<Vec<[f64; 2]>> {
    if flat.len() % 2 != 0 {
        return Err(Error::BadLength { what, len: flat.len(), expected: "a multiple of 2".into() });
    }
    Ok(flat.chunks_exact(2).map(|c| [c[0], c[1]]).collect())
}
