//! The crate's sorts through two instantiations of the standard library's unstable sort:
//! `u64` and `u128` keys. Every generic `sort_unstable_by` is a copy of the whole sorting
//! algorithm (quicksort, heapsort, the small-sort networks: 5–9 KB of wasm each); the call
//! sites had eleven copies, 85 KB of the .wasm before `wasm-opt` (a tenth of its code).
//! Each site packs what it sorts by into one key, with the item's index or payload in its
//! low bits, so that equal keys keep a fixed (the original) order. Three sorts stay generic:
//! the half edges (`topology::half_edges`, built for every depth level of a rendered frame,
//! where a key buffer would be one more allocation a frame) and the matrix columns of
//! `deform::system` and `deform::nonlinear` (their ties are summed, and another tie order
//! would change the normal matrices' last bits).

/// Sorts `keys` ascending.
#[inline(never)]
pub(crate) fn sort_u64(keys: &mut [u64]) {
    keys.sort_unstable();
}

/// Sorts `keys` ascending.
#[inline(never)]
pub(crate) fn sort_u128(keys: &mut [u128]) {
    keys.sort_unstable();
}

/// The bits of `x` as an unsigned key in `f64::total_cmp`'s order (−NaN < −∞ < … < −0 <
/// +0 < … < +∞ < NaN).
pub(crate) fn total_order_key(x: f64) -> u64 {
    let bits = x.to_bits() as i64;
    // total_cmp's flip of the magnitude bits of negative numbers, then the sign bit flipped
    // so that the signed order becomes the unsigned one.
    ((bits ^ (((bits >> 63) as u64) >> 1) as i64) as u64) ^ (1 << 63)
}

/// The `f64` whose [`total_order_key`] is `key`.
pub(crate) fn from_total_order_key(key: u64) -> f64 {
    let t = (key ^ (1 << 63)) as i64;
    f64::from_bits((t ^ (((t >> 63) as u64) >> 1) as i64) as u64)
}

/// Sorts `values` ascending (a copy through `u64` keys).
pub(crate) fn sort_u32(values: &mut [u32]) {
    let mut keys: Vec<u64> = values.iter().map(|&v| v as u64).collect();
    sort_u64(&mut keys);
    for (v, k) in values.iter_mut().zip(keys) {
        *v = k as u32;
    }
}

/// Sorts `items` by `key`, ties in their current order (a stable sort), through `u128`
/// keys: the key in the high 64 bits, the index in the low ones. `scratch` is reused.
pub(crate) fn sort_by_key_stable<T: Copy>(
    items: &mut [T],
    key: impl Fn(&T) -> u64,
    scratch: &mut Vec<u128>,
    copy: &mut Vec<T>,
) {
    scratch.clear();
    scratch.extend(items.iter().enumerate().map(|(i, t)| ((key(t) as u128) << 64) | i as u128));
    sort_u128(scratch);
    copy.clear();
    copy.extend_from_slice(items);
    for (slot, &k) in items.iter_mut().zip(scratch.iter()) {
        *slot = copy[(k as u64) as usize];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn total_order_key_agrees_with_total_cmp() {
        let xs = [
            f64::NEG_INFINITY,
            -1e300,
            -1.0,
            -1e-310,
            -0.0,
            0.0,
            1e-310,
            1.0,
            1e300,
            f64::INFINITY,
            f64::NAN,
            -f64::NAN,
        ];
        for &a in &xs {
            assert_eq!(from_total_order_key(total_order_key(a)).to_bits(), a.to_bits());
            for &b in &xs {
                assert_eq!(total_order_key(a).cmp(&total_order_key(b)), a.total_cmp(&b), "{a} {b}");
            }
        }
    }

    #[test]
    fn stable_by_key() {
        let mut items = [(3u32, 'a'), (1, 'b'), (3, 'c'), (0, 'd'), (1, 'e')];
        let mut expected = items;
        expected.sort_by_key(|t| t.0);
        sort_by_key_stable(&mut items, |t| t.0 as u64, &mut Vec::new(), &mut Vec::new());
        assert_eq!(items, expected);
        let mut v = [5u32, 1, 4, 1, u32::MAX, 0];
        sort_u32(&mut v);
        assert_eq!(v, [0, 1, 1, 4, 5, u32::MAX]);
    }
}
