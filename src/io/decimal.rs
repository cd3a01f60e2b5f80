//! Fixed-point decimal text of a float with nine decimals, the same characters as
//! `format!("{x:.9}")` but without the general formatter's arbitrary-precision path: the frames a
//! run writes hold five such numbers per vertex, and formatting them was most of writing a frame.

use std::fmt::Write;

/// Decimals written by [`push_fixed9`].
const DECIMALS: u32 = 9;

/// `10^DECIMALS`.
const SCALE: u128 = 1_000_000_000;

/// Appends `x` with nine decimals to `out`, character for character what `write!(out, "{x:.9}")`
/// appends: the exact binary value rounded to the nearest multiple of `1e-9`, ties to even, a
/// leading `-` when the sign bit is set (`-0.000000000` included). Values of magnitude `2^53`
/// and more, infinities and NaN take the general formatter.
pub fn push_fixed9(out: &mut String, x: f64) {
    let bits = x.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let fraction = bits & ((1u64 << 52) - 1);
    let (mantissa, exponent) = if biased == 0 {
        (fraction, -1074)
    } else {
        (fraction | (1u64 << 52), biased - 1075)
    };
    if biased == 0x7ff || exponent > 0 {
        let _ = write!(out, "{x:.9}");
        return;
    }
    // x = mantissa * 2^exponent, so x * 10^9 = scaled / 2^shift with scaled < 2^83.
    let scaled = mantissa as u128 * SCALE;
    let shift = exponent.unsigned_abs();
    let units = if shift == 0 {
        scaled
    } else if shift > 100 {
        0 // below 2^-17 of a unit: rounds to zero.
    } else {
        let (quotient, remainder) = (scaled >> shift, scaled & ((1u128 << shift) - 1));
        let half = 1u128 << (shift - 1);
        let up = remainder > half || (remainder == half && quotient & 1 == 1);
        quotient + up as u128
    };
    if bits >> 63 == 1 {
        out.push('-');
    }
    let _ = write!(
        out,
        "{}.{:0width$}",
        units / SCALE,
        units % SCALE,
        width = DECIMALS as usize
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn fixed9(x: f64) -> String {
        let mut s = String::new();
        push_fixed9(&mut s, x);
        s
    }

    #[test]
    fn matches_the_general_formatter_on_edge_values() {
        let ties: Vec<f64> = (0..64).map(|k| (2 * k + 1) as f64 / 1024.0).collect();
        let specials = [
            0.0,
            -0.0,
            -1e-12,
            1e-12,
            5e-10,
            -5e-10,
            4.9999999999e-10,
            0.9999999995,
            0.9999999994999999,
            1.0,
            -1.0,
            123456.123456789,
            f64::MIN_POSITIVE,
            5e-324,
            -5e-324,
            9007199254740991.0,
            9007199254740992.0,
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        for x in ties.iter().chain(&specials).flat_map(|&x| [x, -x]) {
            assert_eq!(fixed9(x), format!("{x:.9}"), "x = {x:e}");
        }
    }

    proptest! {
        #[test]
        fn matches_the_general_formatter_on_any_bits(bits in any::<u64>()) {
            let x = f64::from_bits(bits);
            prop_assert_eq!(fixed9(x), format!("{x:.9}"));
        }

        #[test]
        fn matches_the_general_formatter_on_exact_ties(odd in 0u64..1 << 40, e in 0i32..20) {
            // (2 odd + 1) / 2^(10 + e) times 10^9 ends in exactly one half for e = 0.
            let x = (2 * odd + 1) as f64 / f64::powi(2.0, 10 + e);
            prop_assert_eq!(fixed9(x), format!("{x:.9}"));
        }

        #[test]
        fn matches_the_general_formatter_on_cloth_coordinates(x in -10.0f64..10.0) {
            prop_assert_eq!(fixed9(x), format!("{x:.9}"));
        }
    }
}
