//! Vector helpers in the plane and in space, and bounding boxes: the small geometry every
//! other module shares (meshes, point location, flattening, quality, meshing, rendering).

/// `a − b`.
#[inline(always)]
pub(crate) fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// The z component of `a × b`: twice the signed area of the triangle `(0, a, b)`.
#[inline(always)]
pub(crate) fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// `a · b`.
#[inline(always)]
pub(crate) fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// Vectors in space (3D surfaces: flattening, its quality measures).
pub(crate) mod space {
    /// `a − b`.
    pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    /// `a · b`.
    pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    /// `a × b`.
    pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    }

    /// `|a|`.
    pub(crate) fn norm(a: [f64; 3]) -> f64 {
        dot(a, a).sqrt()
    }
}

/// The bounding box `(lo, hi)` of `points`, in any dimension; `([∞; D], [−∞; D])` when
/// there are none.
pub(crate) fn bounds<const D: usize>(points: impl IntoIterator<Item = [f64; D]>) -> ([f64; D], [f64; D]) {
    let (mut lo, mut hi) = ([f64::INFINITY; D], [f64::NEG_INFINITY; D]);
    for p in points {
        for k in 0..D {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// The length of the diagonal of the bounding box of `points` (0 when there are none): a
/// shape's size, against which tolerances are measured.
pub(crate) fn bbox_diagonal<const D: usize>(points: &[[f64; D]]) -> f64 {
    if points.is_empty() {
        return 0.0;
    }
    let (lo, hi) = bounds(points.iter().copied());
    (0..D).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
}
