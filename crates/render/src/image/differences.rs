//! The per-pixel differences every error figure comes from: for each pixel pair given, the
//! largest RGB channel difference (alpha ignored), as a histogram and a sum. `--diff`'s and
//! the tests' figures (the native library's `metrics`, `compare::diff`) and the browser's
//! compare numbers (`glview export --live`) are read off one of these.
pub struct Differences {
    histogram: [u64; 256],
    sum: u64,
    pixels: u64,
}

/// A pixel counts as wrong when some channel is off by more than this (of 255): the
/// threshold the peers use (Filament accepts 5/255; 8/255 ignores rounding).
pub const WRONG_THRESHOLD: u8 = 8;

impl Differences {
    /// The differences of `pairs` of RGBA8 pixels (each at least 3 bytes).
    pub fn of<'a>(pairs: impl Iterator<Item = (&'a [u8], &'a [u8])>) -> Differences {
        let mut d = Differences {
            histogram: [0; 256],
            sum: 0,
            pixels: 0,
        };
        for (p, q) in pairs {
            let c = [0, 1, 2].map(|i| p[i].abs_diff(q[i]));
            d.sum += c.iter().map(|&v| u64::from(v)).sum::<u64>();
            d.histogram[usize::from(c.into_iter().max().unwrap_or(0))] += 1;
            d.pixels += 1;
        }
        d
    }

    /// How many pixels were compared.
    pub fn pixels(&self) -> u64 {
        self.pixels
    }

    /// Mean absolute difference over the pixels and their RGB channels, 0–255 (0 for none).
    pub fn mean(&self) -> f64 {
        self.sum as f64 / (3 * self.pixels.max(1)) as f64
    }

    /// The `q` quantile of the largest channel difference (rank ⌈q·n⌉, at least 1); 255
    /// when no pixel was compared.
    pub fn percentile(&self, q: f64) -> f64 {
        let rank = (q * self.pixels as f64).ceil().max(1.0) as u64;
        let mut seen = 0;
        for (value, count) in self.histogram.iter().enumerate() {
            seen += count;
            if seen >= rank {
                return value as f64;
            }
        }
        255.0
    }

    /// The largest channel difference anywhere.
    pub fn max(&self) -> f64 {
        self.histogram.iter().rposition(|&c| c > 0).unwrap_or(0) as f64
    }

    /// Share of pixels (0–1) whose largest channel difference exceeds [`WRONG_THRESHOLD`].
    pub fn wrong(&self) -> f64 {
        let over: u64 = self.histogram[usize::from(WRONG_THRESHOLD) + 1..]
            .iter()
            .sum();
        over as f64 / self.pixels.max(1) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_count_the_largest_channel_of_each_pixel() {
        let a = [0u8, 0, 0, 255, 10, 10, 10, 0, 100, 0, 0, 9];
        let b = [0u8, 0, 0, 0, 10, 19, 10, 255, 0, 0, 0, 9];
        let d = Differences::of(a.chunks_exact(4).zip(b.chunks_exact(4)));
        assert_eq!(d.pixels(), 3);
        assert_eq!(d.mean(), 109.0 / 9.0, "alpha ignored");
        assert_eq!(
            (d.max(), d.percentile(0.5), d.percentile(0.99)),
            (100.0, 9.0, 100.0)
        );
        assert_eq!(d.wrong(), 2.0 / 3.0, "9 and 100 are over 8");
        let none = Differences::of(std::iter::empty());
        assert_eq!(
            (none.mean(), none.wrong(), none.percentile(0.99)),
            (0.0, 0.0, 255.0)
        );
    }
}
