//! File names of frame sequences: a pattern with one printf-style integer field, `%d` or
//! `%0Nd` (`frame-%04d.ply` → `frame-0007.ply` for frame 7), as ffmpeg, Blender and pbrt-v4's
//! tools write them. `%%` is a literal `%`. Scene files use it for mesh sequences; the command
//! line for `--frames A..B -o out_%04d.exr`.

/// A parsed pattern: the text before and after its one frame field, and the field's width
/// (zero-padded; 0 = no padding).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FramePattern {
    prefix: String,
    suffix: String,
    width: usize,
}

impl FramePattern {
    /// Parses `pattern`; it must hold exactly one `%d` or `%0Nd` field (N ≤ 9). The error says
    /// what was found.
    pub fn parse(pattern: &str) -> Result<Self, String> {
        let mut cur = String::new();
        let mut prefix = None;
        let mut width = None;
        let mut chars = pattern.chars().peekable();
        while let Some(c) = chars.next() {
            if c != '%' {
                cur.push(c);
                continue;
            }
            match chars.peek() {
                Some('%') => {
                    chars.next();
                    cur.push('%');
                }
                _ => {
                    let mut digits = String::new();
                    while let Some(d) = chars.peek().copied().filter(char::is_ascii_digit) {
                        digits.push(d);
                        chars.next();
                    }
                    if chars.next() != Some('d') || (!digits.is_empty() && !digits.starts_with('0'))
                    {
                        return Err(format!(
                            "'{pattern}': a frame field is %d or %0Nd (e.g. %04d)"
                        ));
                    }
                    let w: usize = if digits.is_empty() {
                        0
                    } else {
                        digits
                            .parse()
                            .map_err(|_| format!("'{pattern}': bad width"))?
                    };
                    if w > 9 {
                        return Err(format!(
                            "'{pattern}': a frame field is at most 9 digits wide"
                        ));
                    }
                    if width.replace(w).is_some() {
                        return Err(format!("'{pattern}' has more than one frame field"));
                    }
                    prefix = Some(std::mem::take(&mut cur));
                }
            }
        }
        let Some(width) = width else {
            return Err(format!(
                "'{pattern}' has no frame field (%d or %0Nd, e.g. frame-%04d.ply)"
            ));
        };
        Ok(Self {
            prefix: prefix.unwrap_or_default(),
            suffix: cur,
            width,
        })
    }

    /// True if `text` holds a frame field (an unescaped `%`).
    pub fn is_pattern(text: &str) -> bool {
        text.replace("%%", "").contains('%')
    }

    /// The pattern with its frame field replaced by `text` (`out_%04d.exr`, "preview" →
    /// `out_preview.exr`).
    pub fn replace_field(&self, text: &str) -> String {
        format!("{}{text}{}", self.prefix, self.suffix)
    }

    /// The file name of `frame` (negative frames get a leading minus sign before the padding).
    pub fn name(&self, frame: i64) -> String {
        let digits = format!("{:0w$}", frame.unsigned_abs(), w = self.width);
        let sign = if frame < 0 { "-" } else { "" };
        format!("{}{sign}{digits}{}", self.prefix, self.suffix)
    }
}

#[cfg(test)]
mod tests {
    use super::FramePattern;

    #[test]
    fn names_frames_like_printf() {
        let p = FramePattern::parse("out/frame-%04d.ply").unwrap();
        assert_eq!(p.name(7), "out/frame-0007.ply");
        assert_eq!(p.name(12345), "out/frame-12345.ply");
        assert_eq!(p.name(-3), "out/frame--0003.ply");
        assert_eq!(FramePattern::parse("f%d.exr").unwrap().name(42), "f42.exr");
        assert_eq!(p.replace_field("preview"), "out/frame-preview.ply");
        assert_eq!(
            FramePattern::parse("100%%_%02d.png").unwrap().name(5),
            "100%_05.png"
        );
    }

    #[test]
    fn refuses_patterns_without_exactly_one_field() {
        for bad in [
            "frame.ply",
            "a%d_%d.ply",
            "a%4d.ply",
            "a%s.ply",
            "a%",
            "a%010d",
        ] {
            assert!(FramePattern::parse(bad).is_err(), "{bad}");
        }
        assert!(FramePattern::is_pattern("x%03d.exr"));
        assert!(!FramePattern::is_pattern("100%%.exr"));
        assert!(!FramePattern::is_pattern("out.exr"));
    }
}
