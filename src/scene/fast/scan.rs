//! A cursor over a chunk's bytes for the numeric statements (`v`, `vn`, `vt`, `f`): numbers
//! are read in place, without first finding the line end or splitting it into words. Only
//! spaces and tabs separate words, and a `\r` only counts before `\n` or at the end of the
//! file (as the old path strips it); any other byte inside a number makes it fail, and the
//! file falls back to the old path, which reads words split at any Unicode whitespace.
use super::num;

pub struct Scan<'a> {
    b: &'a [u8],
    pub i: usize,
}

impl<'a> Scan<'a> {
    pub fn new(b: &'a [u8]) -> Self {
        Scan { b, i: 0 }
    }

    pub fn rest(&self) -> &'a [u8] {
        &self.b[self.i..]
    }

    /// Whether position `j` ends a word.
    #[inline]
    fn sep(&self, j: usize) -> bool {
        match self.b.get(j) {
            None | Some(b' ' | b'\t' | b'\n') => true,
            Some(b'\r') => matches!(self.b.get(j + 1), None | Some(b'\n')),
            _ => false,
        }
    }

    #[inline]
    pub fn blanks(&mut self) {
        while matches!(self.b.get(self.i), Some(b' ' | b'\t')) {
            self.i += 1;
        }
    }

    /// Consumes the line end (`\n`, `\r\n`, or `\r` / nothing at the end of the chunk).
    #[inline]
    pub fn end_line(&mut self) -> bool {
        match self.b.get(self.i) {
            None => true,
            Some(b'\n') => {
                self.i += 1;
                true
            }
            Some(b'\r') if self.sep(self.i) => {
                self.i += if self.i + 1 < self.b.len() { 2 } else { 1 };
                true
            }
            _ => false,
        }
    }

    /// Whether the cursor is at the end of the line (nothing consumed).
    #[inline]
    pub fn at_line_end(&self) -> bool {
        match self.b.get(self.i) {
            None | Some(b'\n') => true,
            Some(b'\r') => self.sep(self.i),
            _ => false,
        }
    }

    /// One word as `f64`, as `str::parse` reads it; decimals of at most 19 digits with a
    /// mantissa up to 2^53 and a power of ten up to 22 are exact in one operation (Clinger's
    /// fast path; the digit limit keeps the u64 from wrapping unnoticed).
    #[inline]
    pub fn float(&mut self) -> Option<f64> {
        let (b, start) = (self.b, self.i);
        let mut j = start;
        let neg = b.get(j) == Some(&b'-');
        if neg || b.get(j) == Some(&b'+') {
            j += 1;
        }
        let mut m = 0u64;
        let int_start = j;
        while let Some(&c) = b.get(j).filter(|c| c.is_ascii_digit()) {
            m = m.wrapping_mul(10).wrapping_add(u64::from(c - b'0'));
            j += 1;
        }
        let mut digits = j - int_start;
        let mut frac = 0;
        if b.get(j) == Some(&b'.') {
            j += 1;
            let frac_start = j;
            while let Some(&c) = b.get(j).filter(|c| c.is_ascii_digit()) {
                m = m.wrapping_mul(10).wrapping_add(u64::from(c - b'0'));
                j += 1;
            }
            frac = j - frac_start;
            digits += frac;
        }
        if digits > 0 && digits <= 19 && m <= 1 << 53 && frac <= 22 && self.sep(j) {
            self.i = j;
            let v = m as f64 / POW10[frac];
            return Some(if neg { -v } else { v });
        }
        // Exponents, long mantissas, `inf`/`nan`: the word goes to the general parser.
        let mut e = start;
        while !self.sep(e) {
            e += 1;
        }
        self.i = e;
        (e > start).then_some(())?;
        num::float(&b[start..e])
    }

    /// A face index: `-`? up to 12 digits (more, or `+`, fall back).
    #[inline]
    pub fn index(&mut self) -> Option<i64> {
        let b = self.b;
        let neg = b.get(self.i) == Some(&b'-');
        let start = self.i + usize::from(neg);
        let mut j = start;
        let mut v: i64 = 0;
        while let Some(&c) = b.get(j).filter(|c| c.is_ascii_digit()) {
            v = v * 10 + i64::from(c - b'0');
            j += 1;
        }
        (j > start && j - start <= 12).then_some(())?;
        self.i = j;
        Some(if neg { -v } else { v })
    }

    /// Consumes `c` if it is next.
    #[inline]
    pub fn eat(&mut self, c: u8) -> bool {
        let hit = self.b.get(self.i) == Some(&c);
        self.i += usize::from(hit);
        hit
    }

    /// Whether the next byte ends a word.
    #[inline]
    pub fn at_sep(&self) -> bool {
        self.sep(self.i)
    }
}

const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_read_as_std_reads_them() {
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
            "0.0000000000000000000001",
            "nan",
            "0.00000000000000000000012",
            "1.2.3",
            "1e",
            ".",
            "-",
            "1x",
            "1\r2",
        ] {
            for tail in ["", " ", "\n", "\r\n", "\t", "\r", " 1.5 2.5\n"] {
                let text = format!("{s}{tail}");
                let mut sc = Scan::new(text.as_bytes());
                let got = sc.float();
                let want = s.parse::<f64>().ok();
                assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits), "{text:?}");
            }
        }
    }
}
