//! Number words of the fast path that [`super::scan`] does not read in place. Floats: plain decimals that fit Clinger's fast path
//! (mantissa ≤ 2^53, power of ten ≤ 22) are exact with one multiplication or division;
//! anything else goes to `str::parse::<f64>`, which is what repair and tobj use, so both
//! paths give the same bits. `None` = not a number the old path would accept either way
//! (the caller then falls back).

const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Parses a whole token as `f64`, with the same result as `str::parse::<f64>`.
pub fn float(tok: &[u8]) -> Option<f64> {
    simple_float(tok).or_else(|| std::str::from_utf8(tok).ok()?.parse().ok())
}

fn simple_float(tok: &[u8]) -> Option<f64> {
    let (neg, rest) = match tok.first()? {
        b'-' => (true, &tok[1..]),
        b'+' => (false, &tok[1..]),
        _ => (false, tok),
    };
    let mut m: u64 = 0;
    let mut digits = 0u32;
    let mut exp: i32 = 0;
    let mut i = 0;
    let mut seen_digit = false;
    while i < rest.len() && rest[i].is_ascii_digit() {
        let d = u64::from(rest[i] - b'0');
        if m != 0 || d != 0 {
            digits += 1;
        }
        m = m.wrapping_mul(10).wrapping_add(d);
        seen_digit = true;
        i += 1;
    }
    if i < rest.len() && rest[i] == b'.' {
        i += 1;
        while i < rest.len() && rest[i].is_ascii_digit() {
            let d = u64::from(rest[i] - b'0');
            if m != 0 || d != 0 {
                digits += 1;
            }
            m = m.wrapping_mul(10).wrapping_add(d);
            exp -= 1;
            seen_digit = true;
            i += 1;
        }
    }
    if !seen_digit || digits > 15 {
        return None;
    }
    if i < rest.len() && (rest[i] | 0x20) == b'e' {
        i += 1;
        let eneg = match rest.get(i) {
            Some(b'-') => {
                i += 1;
                true
            }
            Some(b'+') => {
                i += 1;
                false
            }
            _ => false,
        };
        let start = i;
        let mut e: i32 = 0;
        while i < rest.len() && rest[i].is_ascii_digit() && i - start < 4 {
            e = e * 10 + i32::from(rest[i] - b'0');
            i += 1;
        }
        if i == start {
            return None;
        }
        exp += if eneg { -e } else { e };
    }
    if i != rest.len() || m > 1 << 53 || exp.unsigned_abs() > 22 {
        return None;
    }
    let v = m as f64;
    let v = if exp < 0 {
        v / POW10[exp.unsigned_abs() as usize]
    } else {
        v * POW10[exp as usize]
    };
    Some(if neg { -v } else { v })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_match_std() {
        for s in [
            "0",
            "-0",
            "1.",
            ".5",
            "-.5",
            "+1.25",
            "0.123456",
            "-0.999999",
            "1e5",
            "1E-5",
            "3.14159265358979",
            "123456789012345678",
            "1e300",
            "1e-320",
            "0.1e-22",
            "7e22",
            "9007199254740993",
            "1.7976931348623157e308",
            "inf",
            "nan",
            "1e",
            ".",
            "-",
            "1.2.3",
            "1e+",
            "0x10",
            "1_0",
        ] {
            let want = s.parse::<f64>().ok();
            let got = float(s.as_bytes());
            assert_eq!(
                got.map(f64::to_bits),
                want.map(f64::to_bits),
                "{s}: {got:?} vs {want:?}"
            );
        }
    }
}
