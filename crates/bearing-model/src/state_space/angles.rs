//! Fast angle arithmetic for the ball kinematics: `sin_cos`, `floor_i64` and the two angle
//! wraps into `[0, 2π)`.

use std::f64::consts::TAU;

/// `(sin x, cos x)` within about one ulp of the correctly rounded values, about four times
/// cheaper than libm's `sincos` (which the cage angle needs once per frame): Cody–Waite
/// reduction by π/2 in two 33-bit parts (exact products for |x| < 2²⁰·π/2) and fdlibm's
/// kernels on [−π/4, π/4], tail of the reduced argument included. libm for |x| ≥ 10⁵ rad.
#[inline]
#[allow(clippy::excessive_precision)] // fdlibm's constants, as published
pub(super) fn sin_cos(x: f64) -> (f64, f64) {
    if x.is_nan() || x.abs() >= 1e5 {
        return x.sin_cos();
    }
    const INV_PIO2: f64 = std::f64::consts::FRAC_2_PI;
    const PIO2_1: f64 = 1.570_796_326_734_125_614_17e0;
    const PIO2_2: f64 = 6.077_100_506_303_965_976_60e-11;
    const PIO2_2T: f64 = 2.022_266_248_795_950_631_54e-21;
    const S1: f64 = -1.666_666_666_666_663_243_48e-1;
    const S2: f64 = 8.333_333_333_322_489_461_24e-3;
    const S3: f64 = -1.984_126_982_985_794_931_34e-4;
    const S4: f64 = 2.755_731_370_707_006_767_89e-6;
    const S5: f64 = -2.505_076_025_340_686_341_95e-8;
    const S6: f64 = 1.589_690_995_211_550_102_21e-10;
    const C1: f64 = 4.166_666_666_666_660_190_37e-2;
    const C2: f64 = -1.388_888_888_887_410_957_49e-3;
    const C3: f64 = 2.480_158_728_947_672_941_78e-5;
    const C4: f64 = -2.755_731_435_139_066_330_35e-7;
    const C5: f64 = 2.087_572_321_298_174_827_90e-9;
    const C6: f64 = -1.135_964_755_778_819_482_65e-11;
    // round to nearest by the 1.5·2⁵² trick (no libm call on baseline x86-64)
    const SHIFTER: f64 = 6_755_399_441_055_744.0;
    let fn_ = (x * INV_PIO2 + SHIFTER) - SHIFTER;
    let n = fn_ as i64;
    let t = x - fn_ * PIO2_1; // exact
    let w = fn_ * PIO2_2; // exact
    let r = t - w;
    let w = fn_ * PIO2_2T - ((t - r) - w);
    let y0 = r - w;
    let y1 = (r - y0) - w;
    let z = y0 * y0;
    // fdlibm __kernel_sin(y0, y1, 1)
    let v = z * y0;
    let rs = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    let sn = y0 - ((z * (0.5 * y1 - v * rs) - y1) - v * S1);
    // fdlibm __kernel_cos(y0, y1)
    let rc = z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    let hz = 0.5 * z;
    let wc = 1.0 - hz;
    let cs = wc + (((1.0 - wc) - hz) + (z * rc - y0 * y1));
    match n & 3 {
        0 => (sn, cs),
        1 => (cs, -sn),
        2 => (-sn, -cs),
        _ => (-cs, sn),
    }
}

/// `⌊x⌋` for `|x| < 2⁶³`, bit-identical to `f64::floor` there, without the libm call that
/// baseline x86-64 (no SSE4.1 `roundsd`) makes for `floor`: one truncating conversion.
#[inline(always)]
pub(super) fn floor_i64(x: f64) -> i64 {
    let i = x as i64;
    if (i as f64) > x { i - 1 } else { i }
}

/// Wrap an angle known to lie in `(−2π, 4π)` into `[0, 2π)` without a division.
#[inline(always)]
pub(super) fn wrap_fast(x: f64) -> f64 {
    if x >= TAU {
        let y = x - TAU;
        if y >= TAU { y - TAU } else { y }
    } else if x < 0.0 {
        x + TAU
    } else {
        x
    }
}

/// Wrap any finite angle into `[0, 2π)`.
#[inline(always)]
pub(super) fn wrap(x: f64) -> f64 {
    let y = x - TAU * floor_i64(x * (1.0 / TAU)) as f64;
    if y >= TAU {
        y - TAU
    } else if y < 0.0 {
        0.0
    } else {
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn sin_cos_is_within_two_ulp_of_libm() {
        let mut worst: f64 = 0.0;
        let mut x = -2e5_f64;
        let mut k = 0u64;
        while x < 2e5 {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
            // a deterministic, irregular walk through the range, dense near 0
            k = k
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            x += 1e-3 + (k >> 40) as f64 * 1e-9 * (1.0 + x.abs());
        }
        for x in [
            0.0,
            -0.0,
            1e-300,
            std::f64::consts::FRAC_PI_4,
            -PI,
            PI / 2.0,
            1e5,
            -1e5 + 0.5,
        ] {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
        }
        assert!(worst <= 2.3e-16, "worst {worst:e}");
        assert!(sin_cos(f64::NAN).0.is_nan());
    }

    #[test]
    fn fast_floor_matches_floor() {
        for x in [
            -3.5,
            -3.0,
            -1e-300,
            -0.0,
            0.0,
            1e-300,
            0.5,
            1.0,
            2.999_999_999,
            1e15 + 0.5,
            -1e15 - 0.5,
        ] {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x}");
        }
    }
}
