//! Composing pictures on the CPU: pasting panes into a grid and writing labels with an 8×8
//! bitmap font (`font8x8`, drawn at 2× so it reads at a glance), so labels look the same on
//! every machine without a system font. Labels have one size: a label too long for its pane
//! wraps onto more lines (the strip grows) rather than shrinking.
use crate::image::Rgba;
use font8x8::UnicodeFonts;

/// Height of a one-line label strip: 16-pixel glyphs plus 2-pixel margins.
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

/// Glyph scale of every label: 8×8 glyphs drawn 16×16, one size everywhere.
pub(crate) const SCALE: u32 = 2;
/// Side of a label glyph in pixels.
pub(crate) const GLYPH: u32 = 8 * SCALE;
/// Label lines are this far apart (a glyph and 2 pixels).
const LINE: u32 = GLYPH + 2;
/// Left margin of a label.
const MARGIN: u32 = 4;

/// What the 8×8 font draws for `ch`: its own glyph, or a stand-in of glyphs it has
/// (`→` as `->`, `≥` as `>=`, ...). Characters with neither are drawn as `?`.
pub fn substitute(ch: char) -> std::borrow::Cow<'static, str> {
    let s = match ch {
        '→' => "->",
        '←' => "<-",
        '↔' => "<->",
        '≥' => ">=",
        '≤' => "<=",
        '≠' => "!=",
        '≈' => "~",
        '…' => "...",
        '−' | '–' | '—' => "-",
        '‘' | '’' => "'",
        '“' | '”' => "\"",
        '•' => "\u{b7}",
        _ => return ch.to_string().into(),
    };
    s.into()
}

fn glyph(ch: char) -> Option<[u8; 8]> {
    font8x8::BASIC_FONTS
        .get(ch)
        .or_else(|| font8x8::LATIN_FONTS.get(ch))
        .or_else(|| font8x8::GREEK_FONTS.get(ch))
        .or_else(|| font8x8::BOX_FONTS.get(ch))
}

/// The characters of `text` (after [`substitute`]) the font has no glyph for.
pub fn missing_glyphs(text: &str) -> Vec<char> {
    text.chars()
        .flat_map(|c| substitute(c).chars().collect::<Vec<_>>())
        .filter(|&c| c != ' ' && glyph(c).is_none())
        .collect()
}

/// `text` as the glyphs drawn, substitutions made.
fn drawn(text: &str) -> Vec<char> {
    text.chars()
        .flat_map(|c| substitute(c).chars().collect::<Vec<_>>())
        .collect()
}

/// Writes `text` at (x, y) in `rgb`, each glyph 16×16 pixels.
pub fn text(img: &mut Rgba, x: u32, y: u32, text: &str, rgb: [u8; 3]) {
    text_scaled(img, x, y, text, rgb, SCALE);
}

/// `text` with glyphs of 8·`scale` pixels (the window overlay uses 1).
pub fn text_scaled(img: &mut Rgba, x: u32, y: u32, text: &str, rgb: [u8; 3], scale: u32) {
    let scale = scale.max(1);
    for (i, ch) in drawn(text).into_iter().enumerate() {
        let glyph = glyph(ch)
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

/// `label` broken into lines that fit `width` at the label size: at spaces where it can,
/// inside a word only when the word alone is too long.
pub(crate) fn wrap(width: u32, label: &str) -> Vec<String> {
    let fit = (width.saturating_sub(2 * MARGIN) / GLYPH).max(1) as usize;
    let label: String = drawn(label).into_iter().collect();
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in label.split_whitespace() {
        let mut word: Vec<char> = word.chars().collect();
        let used = line.chars().count();
        if used > 0 && used + 1 + word.len() <= fit {
            line.push(' ');
            line.extend(&word);
            continue;
        }
        if used > 0 {
            lines.push(std::mem::take(&mut line));
        }
        while word.len() > fit {
            lines.push(word.drain(..fit).collect());
        }
        line = word.into_iter().collect();
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}

/// Height of a label strip holding `lines` lines: 2-pixel margins, lines 2 pixels apart
/// (one line: [`STRIP`]).
pub(crate) fn strip_height_lines(lines: usize) -> u32 {
    lines.max(1) as u32 * LINE + 2
}

/// The strip height that holds the longest of `labels` at `width` (panes of one picture
/// share it, so their images line up).
pub fn strip_height(width: u32, labels: &[&str]) -> u32 {
    let lines = labels.iter().map(|l| wrap(width, l).len()).max();
    strip_height_lines(lines.unwrap_or(1))
}

/// Where each glyph of `label` goes in a strip of `width`: (x, y, side) per drawn character,
/// spaces included.
#[cfg(test)] // only the unit tests call it
pub(crate) fn glyph_boxes(width: u32, label: &str) -> Vec<(u32, u32, u32)> {
    wrap(width, label)
        .iter()
        .enumerate()
        .flat_map(|(row, line)| {
            (0..drawn(line).len() as u32)
                .map(move |i| (MARGIN + i * GLYPH, 2 + row as u32 * LINE, GLYPH))
        })
        .collect()
}

/// A label strip `width` × `height` with `label` wrapped on it, every glyph 16×16.
pub fn strip_sized(width: u32, height: u32, label: &str) -> Rgba {
    let mut s = blank(width, height, [24, 24, 28]);
    for (row, line) in wrap(width, label).iter().enumerate() {
        text(&mut s, MARGIN, 2 + row as u32 * LINE, line, [235, 235, 235]);
    }
    s
}

/// A one-line label strip ([`STRIP`] high): what does not fit is cut with an ellipsis
/// (for pictures laid out around one line).
pub(crate) fn strip(width: u32, label: &str) -> Rgba {
    let fit = (width.saturating_sub(2 * MARGIN) / GLYPH).max(1) as usize;
    let chars = drawn(label);
    let line: String = if chars.len() <= fit {
        chars.into_iter().collect()
    } else {
        let keep = fit.saturating_sub(3);
        chars[..keep].iter().collect::<String>() + "..."
    };
    let mut s = blank(width, STRIP, [24, 24, 28]);
    text(&mut s, MARGIN, 2, &line, [235, 235, 235]);
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

    #[test]
    fn label_glyphs_never_overlap_and_have_one_size() {
        let labels = [
            "reference-pbr 3 lights shadows 2048 AgX",
            "phong 3 lights shadows 2048",
            "a-very-long-single-word-label-that-cannot-fit",
            "x",
        ];
        for width in [64u32, 96, 160, 320, 1000] {
            let height = strip_height(width, &labels);
            for label in labels {
                let boxes = glyph_boxes(width, label);
                // Every character is drawn, in one size, inside the strip.
                let text: String = wrap(width, label).concat();
                assert_eq!(boxes.len(), text.chars().count(), "{label}");
                assert!(label
                    .chars()
                    .filter(|c| *c != ' ')
                    .all(|c| text.contains(c)));
                for &(x, y, side) in &boxes {
                    assert_eq!(side, GLYPH);
                    assert!(x + side <= width.max(MARGIN + GLYPH) && y + side <= height);
                }
                for (i, a) in boxes.iter().enumerate() {
                    for b in &boxes[i + 1..] {
                        let apart = a.0 + a.2 <= b.0
                            || b.0 + b.2 <= a.0
                            || a.1 + a.2 <= b.1
                            || b.1 + b.2 <= a.1;
                        assert!(apart, "{label} at {width}: {a:?} and {b:?}");
                    }
                }
            }
        }
        assert_eq!(strip_height(1000, &["one line"]), STRIP);
    }

    #[test]
    fn one_line_strips_cut_long_labels() {
        let s = strip(100, "a label far longer than one hundred pixels");
        assert_eq!((s.width, s.height), (100, STRIP));
        // 5 glyphs fit in 100 - 8 pixels: "a ..." is drawn in full, nothing past the edge.
        assert_eq!(glyph_boxes(100, "abcde").len(), 5);
    }

    #[test]
    fn substitutes_are_in_the_font() {
        for c in "→←↔≥≤≠≈…−–—‘’“”•·×±°²".chars() {
            assert!(missing_glyphs(&c.to_string()).is_empty(), "{c}");
        }
        assert_eq!(missing_glyphs("☃"), ['☃']);
    }
}
