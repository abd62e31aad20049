//! A cursor over a chunk's bytes for the numeric statements (`v`, `vn`, `vt`, `f`): numbers
//! are read in place, without first finding the line end or splitting it into words. Only
//! spaces and tabs separate words, and a `\r` only counts before `\n` or at the end of the
//! file (as the old path strips it); any other byte inside a number makes it fail, and the
//! file falls back to the old path, which reads words split at any Unicode whitespace.
pub(crate) struct Scan<'a> {
    b: &'a [u8],
    pub(crate) i: usize,
}

impl<'a> Scan<'a> {
    pub(crate) fn new(b: &'a [u8]) -> Self {
        Scan { b, i: 0 }
    }

    pub(crate) fn rest(&self) -> &'a [u8] {
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
    pub(crate) fn blanks(&mut self) {
        while matches!(self.b.get(self.i), Some(b' ' | b'\t')) {
            self.i += 1;
        }
    }

    /// Consumes the line end (`\n`, `\r\n`, or `\r` / nothing at the end of the chunk).
    #[inline]
    pub(crate) fn end_line(&mut self) -> bool {
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
    pub(crate) fn at_line_end(&self) -> bool {
        match self.b.get(self.i) {
            None | Some(b'\n') => true,
            Some(b'\r') => self.sep(self.i),
            _ => false,
        }
    }

    /// One word as `f64`, exactly as `str::parse::<f64>` reads it (what the repair pass and
    /// tobj use, so both paths give the same bits), or `None` where `str::parse` refuses the
    /// word (the file then falls back to the old path).
    ///
    /// Decimals are read in place by the `fast-float2` crate: Eisel–Lemire with a correctly
    /// rounded big-decimal fallback, the algorithm the standard library uses too, so the
    /// value is the correctly rounded one `str::parse` gives. (A hand-written Clinger fast
    /// path did this before; it covered short mantissas and small powers of ten only, and
    /// sent everything else through `str::parse`.) Its decimal grammar is the standard
    /// library's, `[+-]? (d+ | d+. d* | d*. d+) ([eE] [+-]? d+)?` (`5.`, `.5`, `+.5` taken;
    /// `.`, `1e`, hex and `_` refused), but it reads a *prefix*: it stops at the first byte
    /// that cannot continue the number (`1e` → `1`, `1.2.3` → `1.2`, `0x10` → `0`,
    /// `1_0` → `1`), and takes `inf`, `infinity` and `nan` as prefixes too (`infx` → `inf`,
    /// `nan(1)` → `nan`). So its value is used only when it is finite and the number ends
    /// where the word ends (at a separator). Anything else (a word with other bytes, `inf`,
    /// `nan`, a decimal that overflows to infinity, an empty word) goes to `str::parse` on the
    /// whole word, which decides acceptance and value exactly as before.
    #[inline]
    pub(crate) fn float(&mut self) -> Option<f64> {
        let (b, start) = (self.b, self.i);
        if let Ok((x, n)) = fast_float2::parse_partial::<f64, _>(&b[start..]) {
            if x.is_finite() && self.sep(start + n) {
                self.i = start + n;
                return Some(x);
            }
        }
        let mut e = start;
        while !self.sep(e) {
            e += 1;
        }
        self.i = e;
        (e > start).then_some(())?;
        std::str::from_utf8(&b[start..e]).ok()?.parse().ok()
    }

    /// A face index: `-`? up to 12 digits (more, or `+`, fall back).
    #[inline]
    pub(crate) fn index(&mut self) -> Option<i64> {
        let b = self.b;
        let neg = b.get(self.i) == Some(&b'-');
        let start = self.i + usize::from(neg);
        let mut j = start;
        let mut v: i64 = 0;
        while let Some(&c) = b.get(j).filter(|c| c.is_ascii_digit()) {
            // Wrapping: 19 digits or more overflow i64 (a panic with overflow checks, found by
            // the fuzzer), and more than 12 are refused below before `v` is used.
            v = v.wrapping_mul(10).wrapping_add(i64::from(c - b'0'));
            j += 1;
        }
        (j > start && j - start <= 12).then_some(())?;
        self.i = j;
        Some(if neg { -v } else { v })
    }

    /// Consumes `c` if it is next.
    #[inline]
    pub(crate) fn eat(&mut self, c: u8) -> bool {
        let hit = self.b.get(self.i) == Some(&c);
        self.i += usize::from(hit);
        hit
    }

    /// Whether the next byte ends a word.
    #[inline]
    pub(crate) fn at_sep(&self) -> bool {
        self.sep(self.i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Scan::float` on `word` followed by each kind of word end, against `str::parse`.
    fn check(word: &str) {
        for tail in ["", " ", "\n", "\r\n", "\t", "\r", " 1.5 2.5\n"] {
            let text = format!("{word}{tail}");
            let mut sc = Scan::new(text.as_bytes());
            let got = sc.float();
            let want = word.parse::<f64>().ok();
            assert_eq!(
                got.map(f64::to_bits),
                want.map(f64::to_bits),
                "{text:?}: {got:?}, str::parse gives {want:?}"
            );
            if got.is_some() {
                assert_eq!(sc.i, word.len(), "{text:?}: the word is consumed");
            }
        }
    }

    #[test]
    fn words_read_as_std_reads_them() {
        for s in [
            // Plain decimals, signs, missing integer or fraction digits.
            "0",
            "-0",
            "+0",
            "1.",
            "5.",
            ".5",
            "-.5",
            "+.5",
            "+1.25",
            "0.123456",
            "-0.999999",
            "3.14159265358979",
            "0.0000000000000000000001",
            "0.00000000000000000000012",
            // Exponents.
            "1e5",
            "1E-5",
            "1e+5",
            "1E+05",
            "1.e5",
            "-.5e-3",
            "0e999999999999999999",
            "1e300",
            "1e-320",
            "0.1e-22",
            "7e22",
            "1e23",
            "1e-400",
            "-1e-400",
            "1e400",
            "-1e400",
            "1e99999999999999999999",
            // Long mantissas, halfway and boundary cases (correct rounding).
            "123456789012345678",
            "9007199254740993",
            "9007199254740992.5",
            "12345678901234567890123",
            "0.1000000000000000055511151231257827",
            "1.7976931348623157e308",
            "1.7976931348623158e308",
            "1.7976931348623159e308",
            "2.2250738585072011e-308",
            "2.2250738585072014e-308",
            "4.9e-324",
            "2.4703282292062327e-324",
            "2.4703282292062328e-324",
            // Infinities and NaNs: taken by str::parse, case-insensitive, with a sign.
            "inf",
            "-inf",
            "+inf",
            "INF",
            "infinity",
            "-Infinity",
            "nan",
            "-nan",
            "+NaN",
            // Refused by str::parse (and so by the fast path).
            "",
            "1e",
            "1e+",
            "1e-",
            ".",
            "-",
            "+",
            "+-1",
            "--1",
            "e5",
            ".e5",
            "1.2.3",
            "1x",
            "1\r2",
            "1e5.5",
            "1e5e5",
            "0x10",
            "0x1p3",
            "1_0",
            "1,5",
            "infin",
            "infx",
            "infinityy",
            "nana",
            "nan(1)",
            "- 1",
            "١",
        ] {
            check(s);
        }
        // More digits than the mantissa and the decimal fallback hold.
        check(&format!("0.{}1", "0".repeat(400)));
        check(&format!("1{}", "0".repeat(320)));
        check(&format!("{}e-800", "7".repeat(800)));
        // Exactly half the smallest subnormal (rounds to even: 0), and just above it.
        const HALF: &str = concat!(
            "2.47032822920623272088284396434110686182529901307162382212792841250337753635104375\
             93264991818081799618989828234772285886546332835517796989819938739800539093906315\
             03565951557022639229085839244910518443593180284993653615250031937045767824921936\
             56236698636584807570015857692699037063119282795585513329278343384093519780155312\
             46597263579574622766465272827220056374006485499977096599470454020828166226237857\
             39345073633900796776193057750674017632467360096895134053553745851666113422376667\
             86041621596804619144672918403005300575308490487653917113865916462395249126236538\
             81879636239373280423891018672348497668235089863388587925628302755995657524455507\
             25518931369083625477918694866799496832404970582102851318545139621383772282614543\
             7693412532098591327667236328125",
            "e-324"
        );
        check(HALF);
        check(&HALF.replace("e-324", "1e-324"));
    }

    /// Random words from the characters numbers are made of, against `str::parse`.
    #[test]
    fn random_words_read_as_std_reads_them() {
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        let mut next = move |n: u64| {
            x ^= x >> 12;
            x ^= x << 25;
            x ^= x >> 27;
            x.wrapping_mul(0x2545_F491_4F6C_DD1D) % n
        };
        let alphabet = b"0123456789012345678901234567890123456789..eE+-+-infatyx";
        for _ in 0..200_000 {
            let len = 1 + next(24) as usize;
            let word: String = (0..len)
                .map(|_| alphabet[next(alphabet.len() as u64) as usize] as char)
                .collect();
            check(&word);
        }
        // Well-formed decimals with many digits and exponents near the limits.
        for _ in 0..100_000 {
            let int: String = (0..next(25))
                .map(|_| char::from(b'0' + next(10) as u8))
                .collect();
            let frac: String = (0..next(25))
                .map(|_| char::from(b'0' + next(10) as u8))
                .collect();
            let sign = ["", "-", "+"][next(3) as usize];
            let exp = match next(3) {
                0 => String::new(),
                _ => format!("e{}", next(700) as i64 - 350),
            };
            check(&format!("{sign}{int}.{frac}{exp}"));
            check(&format!("{sign}{int}{exp}"));
        }
    }
}
