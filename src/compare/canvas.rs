//! Composing pictures on the CPU: pasting panes into a grid and writing labels with an 8×8
//! bitmap font (`font8x8`, drawn at 2× so it reads at a glance), so labels look the same on
//! every machine without a system font.
use crate::image_out::Rgba;
use font8x8::UnicodeFonts;

/// Height of a label strip: 8-pixel glyphs at scale 2 plus a margin.
pub const STRIP: u32 = 20;

pub fn blank(width: u32, height: u32, rgb: [u8; 3]) -> Rgba {
    Rgba {
        width,
        height,
        data: [rgb[0], rgb[1], rgb[2], 255].repeat((width * height) as usize),
    }
}

/// Copies `src` into `dst` with its top-left corner at (x, y) (clipped).
pub fn paste(dst: &mut Rgba, src: &Rgba, x: u32, y: u32) {
    for row in 0..src.height.min(dst.height.saturating_sub(y)) {
        let w = src.width.min(dst.width.saturating_sub(x)) as usize;
        let s = (row * src.width) as usize * 4;
        let d = (((y + row) * dst.width) + x) as usize * 4;
        dst.data[d..d + w * 4].copy_from_slice(&src.data[s..s + w * 4]);
    }
}

/// Writes `text` at (x, y) in `rgb`, each glyph 16×16 pixels; characters the font lacks are
/// drawn as '?'.
pub fn text(img: &mut Rgba, x: u32, y: u32, text: &str, rgb: [u8; 3]) {
    text_scaled(img, x, y, text, rgb, 2);
}

/// [`text`] with glyphs of 8·`scale` pixels.
pub fn text_scaled(img: &mut Rgba, x: u32, y: u32, text: &str, rgb: [u8; 3], scale: u32) {
    let scale = scale.max(1);
    for (i, ch) in text.chars().enumerate() {
        let glyph = font8x8::BASIC_FONTS
            .get(ch)
            .or_else(|| font8x8::LATIN_FONTS.get(ch))
            .or_else(|| font8x8::BASIC_FONTS.get('?'))
            .unwrap_or([0; 8]);
        let gx = x + i as u32 * 8 * scale;
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..8u32 {
                if bits & (1 << col) == 0 {
                    continue;
                }
                for dy in 0..scale {
                    for dx in 0..scale {
                        let (px, py) = (gx + col * scale + dx, y + row as u32 * scale + dy);
                        if px < img.width && py < img.height {
                            let o = ((py * img.width + px) * 4) as usize;
                            img.data[o..o + 3].copy_from_slice(&rgb);
                        }
                    }
                }
            }
        }
    }
}

/// A label strip of `width` with `label` on it, at half size when it would not fit.
pub fn strip(width: u32, label: &str) -> Rgba {
    let mut s = blank(width, STRIP, [24, 24, 28]);
    let fits = 8 + label.chars().count() as u32 * 16 <= width;
    let (scale, y) = if fits { (2, 2) } else { (1, 6) };
    text_scaled(&mut s, 4, y, label, [235, 235, 235], scale);
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_and_paste() {
        let mut img = blank(40, 20, [0, 0, 0]);
        text(&mut img, 0, 0, "A", [255, 255, 255]);
        assert!(img.data.chunks_exact(4).any(|p| p[0] == 255));
        let mut big = blank(50, 30, [9, 9, 9]);
        paste(&mut big, &img, 10, 10);
        assert_eq!(big.pixel(10, 10), img.pixel(0, 0));
        assert_eq!(big.pixel(0, 0)[0], 9);
    }
}
