//! Parsers for command-line numbers whose range the renderer's option types do not cover.

/// A finite number (exposures in stops): `nan` and `inf` are refused.
pub fn finite_f32(s: &str) -> Result<f32, String> {
    let v: f32 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("must be a finite number, got {s}"))
    }
}

#[cfg(test)]
mod tests {
    use super::finite_f32;

    #[test]
    fn finite_numbers_only() {
        assert_eq!(finite_f32("-1.5"), Ok(-1.5));
        for bad in ["nan", "inf", "-inf", "one", ""] {
            assert!(finite_f32(bad).is_err(), "{bad}");
        }
    }
}
