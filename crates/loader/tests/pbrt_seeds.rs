//! The pbrt-v4 scenes of `scenes/pbrt-v4/` and the pbrt fuzz seeds load and build without
//! errors (the seeds stay meaningful starting points for the fuzzer), and the seed of extra
//! features reports what it approximates.

use caustica_loader::load_pbrt;
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn pbrt_scenes_and_fuzz_seeds_load_and_build() {
    let mut n = 0;
    for dir in ["scenes/pbrt-v4", "fuzz/seeds/pbrt"] {
        for e in std::fs::read_dir(root().join(dir)).expect("folder") {
            let path = e.expect("entry").path();
            if path.extension().and_then(|x| x.to_str()) != Some("pbrt") {
                continue;
            }
            // Seeds are copies of the scenes; their meshes are not next to them.
            if dir.starts_with("fuzz") && path.file_name().is_some_and(|f| f != "features.pbrt") {
                continue;
            }
            let b = load_pbrt(&path).unwrap_or_else(|e| panic!("{e}"));
            b.build()
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            n += 1;
        }
    }
    assert_eq!(n, 6);
}

#[test]
fn the_feature_seed_reports_its_approximations() {
    let b = load_pbrt(&root().join("fuzz/seeds/pbrt/features.pbrt")).unwrap();
    let w = b.warnings.join("\n");
    for want in [
        "coateddiffuse rendered as Phong",
        "spot falloff",
        "Option",
        "sampler \"stratified\"",
    ] {
        assert!(w.contains(want), "{want}: {w}");
    }
    assert_eq!(b.settings.spp, Some(4));
    assert_eq!(b.settings.integrator.as_deref(), Some("sppm"));
}
