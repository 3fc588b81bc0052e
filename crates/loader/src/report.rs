//! What a scene loader did not take as written: the ONE warning listing the items it ignored and
//! the one listing what it approximated, each item with its `file:line` (Mitsuba XML, pbrt-v4).

use caustica_scene::SceneBuilder;

/// Adds to `b`'s warnings the list of `ignored` items and of `approximated` ones, if any, each
/// prefixed with the format's name (`"Mitsuba scene"`, `"pbrt scene"`).
pub(crate) fn push_warnings(
    b: &mut SceneBuilder,
    format: &str,
    ignored: &[String],
    approximated: &[String],
) {
    if !ignored.is_empty() {
        b.warnings.push(format!(
            "{format}: ignored {} unsupported item(s): {}",
            ignored.len(),
            ignored.join("; ")
        ));
    }
    if !approximated.is_empty() {
        b.warnings.push(format!(
            "{format}: approximated: {}",
            approximated.join("; ")
        ));
    }
}
