//! The discrete spectral grid: DFT bins of a `T × T` power spectrum, their signed frequencies,
//! their mirror images `f ↦ −f` and the half plane on which sub-strata are drawn (§4.3).

use spectex_spectrum::signed_frequency;

/// A DFT bin `[k, l]` (row, column) of an uncentred `T × T` spectrum: frequency
/// `(f_y, f_x) = (signed_frequency(k, T), signed_frequency(l, T))` cycles per pixel.
pub type Bin = [usize; 2];

/// The frequency `[f_x, f_y]` of `bin`, in cycles per pixel (signed, in `[−½, ½]`).
#[must_use]
pub fn frequency(bin: Bin, size: usize) -> [f64; 2] {
    [
        signed_frequency(bin[1], size),
        signed_frequency(bin[0], size),
    ]
}

/// The bin of frequency `−f`: `[(T − k) mod T, (T − l) mod T]`.
#[must_use]
pub fn mirror(bin: Bin, size: usize) -> Bin {
    if size == 0 {
        return bin;
    }
    [(size - bin[0] % size) % size, (size - bin[1] % size) % size]
}

/// Whether `bin` lies on the half plane where sub-strata are drawn (§4.3: "since the spectrum is
/// symmetric it is applied on half of it"): `f_y > 0`, or `f_y = 0` and `f_x ≥ 0`, in signed
/// frequencies.
///
/// One refinement makes it a true half of the periodic grid: for even `T` the row `f_y = ½`
/// (`k = T/2`) is its own mirror (`−½ ≡ ½`), so it is treated like the row `f_y = 0` and only
/// its `f_x ≥ 0` bins belong to the half plane. With it, of every pair `{f, −f}` of distinct
/// bins exactly one is on the half plane, and every self-mirrored bin is on it (tested).
#[must_use]
pub fn in_half_plane(bin: Bin, size: usize) -> bool {
    let [fx, fy] = frequency(bin, size);
    if fy == 0.0 || fy == 0.5 {
        fx >= 0.0
    } else {
        fy > 0.0
    }
}

/// The representative of `{bin, mirror(bin)}` on the half plane.
#[must_use]
pub fn half_plane_representative(bin: Bin, size: usize) -> Bin {
    if in_half_plane(bin, size) {
        bin
    } else {
        mirror(bin, size)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn half_plane_holds_exactly_one_of_each_mirror_pair() {
        for size in [1usize, 2, 3, 4, 5, 8, 9, 16, 17] {
            for k in 0..size {
                for l in 0..size {
                    let b = [k, l];
                    let m = mirror(b, size);
                    assert_eq!(mirror(m, size), b, "size {size}, bin {b:?}");
                    if m == b {
                        assert!(in_half_plane(b, size), "size {size}: self-mirrored {b:?}");
                    } else {
                        assert_ne!(
                            in_half_plane(b, size),
                            in_half_plane(m, size),
                            "size {size}: pair {b:?} / {m:?}"
                        );
                    }
                    assert!(in_half_plane(half_plane_representative(b, size), size));
                }
            }
        }
    }

    pub fn mirror_negates_the_signed_frequency_except_on_nyquist_lines() {
        for size in [4usize, 7, 16] {
            for k in 0..size {
                for l in 0..size {
                    let f = frequency([k, l], size);
                    let g = frequency(mirror([k, l], size), size);
                    for axis in 0..2 {
                        let nyquist = f[axis] == 0.5;
                        assert!(
                            g[axis] == -f[axis] || (nyquist && g[axis] == 0.5),
                            "size {size}, bin [{k}, {l}], axis {axis}: {f:?} vs {g:?}"
                        );
                    }
                }
            }
        }
    }
}
