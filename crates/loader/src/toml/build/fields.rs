//! Fields that a table sets but that do not apply to its type.

use crate::error::LoadError;
use crate::toml::context::Ctx;
use std::ops::Range;

/// Fails with a Parse error at `span` if any field in `present` is set but not in `allowed`.
pub(crate) fn check_fields(
    cx: &Ctx,
    span: &Range<usize>,
    what: &str,
    present: &[(&str, bool)],
    allowed: &[&str],
) -> Result<(), LoadError> {
    for (name, set) in present {
        if *set && !allowed.contains(name) {
            return Err(cx.err(
                span.clone(),
                format!("field '{name}' does not apply to {what}"),
            ));
        }
    }
    Ok(())
}
