//! Value parsers of the options: each range and its message, in one place.

pub(crate) fn parse_bytes(s: &str) -> Result<u64, String> {
    let s = s.trim();
    let (num, shift) = match s.as_bytes().last() {
        Some(b'K' | b'k') => (&s[..s.len() - 1], 10),
        Some(b'M' | b'm') => (&s[..s.len() - 1], 20),
        Some(b'G' | b'g') => (&s[..s.len() - 1], 30),
        _ => (s, 0),
    };
    num.parse::<u64>()
        .ok()
        .and_then(|n| n.checked_mul(1 << shift))
        .ok_or_else(|| format!("{s:?}: expected bytes, e.g. 1G, 512M or 1048576"))
}

pub(crate) fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or("size must be WxH, e.g. 800x600")?;
    let w: u32 = w.trim().parse().map_err(|_| format!("bad width {w:?}"))?;
    let h: u32 = h.trim().parse().map_err(|_| format!("bad height {h:?}"))?;
    if w == 0 || h == 0 || w > 32768 || h > 32768 {
        return Err(format!("size {w}x{h} out of range (1..32768)"));
    }
    Ok((w, h))
}

/// A finite number > 0; negative numbers reach here (`allow_negative_numbers`) so the error
/// says what is wrong instead of clap's "use -- -1" hint.
pub(crate) fn parse_positive(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        Ok(_) => Err(format!("{s} is out of range: must be a positive number")),
        Err(_) => Err(format!("{s:?} is not a number")),
    }
}

pub(crate) fn parse_bias(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if (0.0..=1.0).contains(&x) => Ok(x),
        Ok(_) => Err(format!(
            "{s} is out of range: the bias is in depth-buffer units, 0..1"
        )),
        Err(_) => Err(format!("{s:?} is not a number")),
    }
}

pub(crate) fn parse_crease(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(d) if (0.0..=180.0).contains(&d) => Ok(d),
        _ => Err(format!("crease angle must be 0..180 degrees, not {s:?}")),
    }
}

pub(crate) fn parse_pcf(s: &str) -> Result<u8, String> {
    match s {
        "1" | "4" | "9" | "16" => Ok(s.parse().unwrap_or(1)),
        _ => Err("PCF taps must be 1, 4, 9 or 16".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_counts() {
        assert_eq!(parse_bytes("1G"), Ok(1 << 30));
        assert_eq!(parse_bytes("512M"), Ok(512 << 20));
        assert_eq!(parse_bytes("1000"), Ok(1000));
        assert!(parse_bytes("lots").is_err());
    }

    #[test]
    fn sizes() {
        assert_eq!(parse_size("640x480"), Ok((640, 480)));
        assert!(parse_size("0x480").is_err());
        assert!(parse_size("640").is_err());
    }
}
