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

/// A value an option's check reads: the value itself, or an optional one (None passes).
pub(crate) trait Checked<T> {
    fn value(&self) -> Option<T>;
}

macro_rules! checked {
    ($($t:ty),*) => {$(
        impl Checked<$t> for $t {
            fn value(&self) -> Option<$t> {
                Some(*self)
            }
        }
        impl Checked<$t> for Option<$t> {
            fn value(&self) -> Option<$t> {
                *self
            }
        }
    )*};
}
checked!(f32, u32, u8);

/// `lo..=hi`.
pub(crate) fn in_range<T, V>(lo: T, hi: T) -> impl Fn(&V) -> Result<(), String>
where
    T: PartialOrd + std::fmt::Display + Copy,
    V: Checked<T>,
{
    move |v| match v.value() {
        Some(x) if !(lo..=hi).contains(&x) => Err(format!(
            "{x} is out of range: must be between {lo} and {hi}"
        )),
        _ => Ok(()),
    }
}

/// At least `lo`.
pub(crate) fn at_least<T, V>(lo: T) -> impl Fn(&V) -> Result<(), String>
where
    T: PartialOrd + std::fmt::Display + Copy,
    V: Checked<T>,
{
    move |v| match v.value() {
        Some(x) if x < lo => Err(format!("{x} is out of range: must be at least {lo}")),
        _ => Ok(()),
    }
}

/// One of these values, else `message`.
pub(crate) fn one_of<T, V>(
    allowed: &'static [T],
    message: &'static str,
) -> impl Fn(&V) -> Result<(), String>
where
    T: PartialEq + std::fmt::Display + Copy,
    V: Checked<T>,
{
    move |v| match v.value() {
        Some(x) if !allowed.contains(&x) => Err(format!("{x}: {message}")),
        _ => Ok(()),
    }
}

/// A finite number > 0.
pub(crate) fn positive(v: &f32) -> Result<(), String> {
    if v.is_finite() && *v > 0.0 {
        Ok(())
    } else {
        Err(format!("{v} is out of range: must be a positive number"))
    }
}

pub(crate) fn positive_or_none(v: &Option<f32>) -> Result<(), String> {
    v.as_ref().map_or(Ok(()), positive)
}

/// 0..1, or unset.
pub(crate) fn unit_or_none(v: &Option<f32>) -> Result<(), String> {
    match v {
        Some(x) if !(0.0..=1.0).contains(x) => {
            Err(format!("{x} is out of range: must be between 0 and 1"))
        }
        _ => Ok(()),
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
