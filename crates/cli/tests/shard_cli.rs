//! `render --shard I/N` and `merge` end to end (issue 24): shards rendered by separate processes
//! in any order (their index given, or read from the variables Slurm and Kubernetes set) merge
//! into the unsharded image's bytes; merge refuses a missing shard, a duplicate, a part of
//! another scene, seed, option set, image size or caustica version, and a corrupted or truncated
//! file, each with a message naming the file, and then writes nothing; bad `--shard` values fail
//! cleanly.

mod common;

use caustica_render::partial::Part;
use common::{assert_clean_failure, stderr, stdout};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The render every test shards: the light tracer on a small film (several light-path chunks).
const RENDER: &[&str] = &[
    "render",
    "caustic-box",
    "--integrator",
    "lighttrace",
    "--spp",
    "100",
    "--width",
    "32",
    "--height",
    "24",
    "-q",
];

fn run(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_caustica"));
    c.args(args);
    for var in [
        "SLURM_ARRAY_TASK_ID",
        "SLURM_ARRAY_TASK_MIN",
        "JOB_COMPLETION_INDEX",
    ] {
        c.env_remove(var);
    }
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run caustica")
}

fn dir(name: &str) -> PathBuf {
    let d = common::tmp_in("shard-cli", name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Renders shard `shard` ("I/N" or "/N" with `env`) of RENDER plus `extra` into `out`.
fn shard(shard: &str, out: &Path, extra: &[&str], env: &[(&str, &str)]) -> Output {
    let mut args = RENDER.to_vec();
    args.extend_from_slice(extra);
    let out = out.to_str().unwrap();
    args.extend_from_slice(&["--shard", shard, "-o", out]);
    let o = run(&args, env);
    assert!(o.status.success(), "shard {shard}: {}", stderr(&o));
    o
}

fn merge(parts: &[&Path], out: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["merge", "-q", "-o", out.to_str().unwrap()];
    args.extend(parts.iter().map(|p| p.to_str().unwrap()));
    args.extend_from_slice(extra);
    run(&args, &[])
}

fn part_name(d: &Path, i: u32, n: u32) -> PathBuf {
    d.join(format!("shard-{i:04}-of-{n:04}.cpart"))
}

#[test]
fn shards_from_any_engine_merge_into_the_unsharded_bytes() {
    let d = dir("exact");
    let whole = d.join("whole.exr");
    let mut args = RENDER.to_vec();
    args.extend_from_slice(&["-o", whole.to_str().unwrap()]);
    let o = run(&args, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let parts = d.join("parts/");
    // Shard 2 by Slurm's variables (a resubmitted subset: MIN is not subtracted), 0 by
    // Kubernetes', 1 given.
    shard(
        "/3",
        &parts,
        &[],
        &[("SLURM_ARRAY_TASK_ID", "2"), ("SLURM_ARRAY_TASK_MIN", "2")],
    );
    shard("/3", &parts, &[], &[("JOB_COMPLETION_INDEX", "0")]);
    let o = shard("1/3", &parts, &[], &[]);
    let said = stdout(&o);
    assert!(
        said.contains("shard 1/3 (light-path chunks") && said.contains("shard-0001-of-0003.cpart"),
        "{said}"
    );
    for i in 0..3 {
        assert!(part_name(&parts, i, 3).exists(), "shard {i}");
    }
    // A shard's temporary file (one still writing, or killed) is not a part.
    std::fs::write(parts.join("shard-0001-of-0003.partial.cpart"), b"half").unwrap();
    let merged = d.join("merged.exr");
    let o = merge(&[&parts], &merged, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("merged 3 of 3 shards"),
        "{}",
        stdout(&o)
    );
    assert_eq!(
        std::fs::read(&merged).unwrap(),
        std::fs::read(&whole).unwrap(),
        "the merge of 3 shards is not the unsharded image"
    );
    // Files in another order give the same bytes.
    let again = d.join("again.exr");
    let (p0, p1, p2) = (
        part_name(&parts, 0, 3),
        part_name(&parts, 1, 3),
        part_name(&parts, 2, 3),
    );
    let o = merge(&[&p2, &p0, &p1], &again, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(&again).unwrap(),
        std::fs::read(&whole).unwrap()
    );
    // A tree of merges: shards 0 and 2 into one part, then with shard 1.
    let inner = d.join("inner.cpart");
    let o = merge(&[&p2, &p0], &inner, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("holding shards 0, 2 of 3"),
        "{}",
        stdout(&o)
    );
    let tree = d.join("tree.exr");
    let o = merge(&[&p1, &inner], &tree, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(&tree).unwrap(),
        std::fs::read(&whole).unwrap(),
        "a two-level merge is not the unsharded image"
    );
    // A shard given again beside a merged part holding it is refused.
    let o = merge(&[&inner, &p0, &p1], &d.join("twice.exr"), &[]);
    assert_clean_failure(&o, &["both hold shard 0/3"]);
}

#[test]
fn merge_refuses_parts_that_do_not_make_one_render_and_writes_nothing() {
    let d = dir("refuse");
    let parts = d.join("parts/");
    for i in 0..3 {
        shard(&format!("{i}/3"), &parts, &[], &[]);
    }
    let (p0, p1, p2) = (
        part_name(&parts, 0, 3),
        part_name(&parts, 1, 3),
        part_name(&parts, 2, 3),
    );
    let out = d.join("out.exr");
    let refused = |parts: &[&Path], says: &[&str]| {
        let o = merge(parts, &out, &[]);
        assert_clean_failure(&o, says);
        assert!(!out.exists(), "a refused merge wrote {}", out.display());
    };
    // A missing shard; a preview with --partial.
    refused(
        &[&p0, &p2],
        &["shards missing: 1 of 3 (2 given)", "--partial"],
    );
    let o = merge(&[&p0, &p2], &out, &["--partial"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("1 of 3 shards missing"),
        "{}",
        stderr(&o)
    );
    std::fs::remove_file(&out).unwrap();
    // A duplicate.
    let copy = d.join("copy.cpart");
    std::fs::copy(&p1, &copy).unwrap();
    refused(
        &[&p0, &p1, &copy, &p2],
        &["copy.cpart", "both hold shard 1/3"],
    );
    // Another scene, seed, option set, image size.
    let other = |name: &str, extra: &[&str]| {
        let p = d.join(format!("{name}.cpart"));
        shard("1/3", &p, extra, &[]);
        p
    };
    let scene = d.join("scene.cpart");
    let mut args: Vec<&str> = RENDER
        .iter()
        .map(|a| {
            if *a == "caustic-box" {
                "glass-sphere"
            } else {
                a
            }
        })
        .collect();
    args.extend_from_slice(&["--shard", "1/3", "-o", scene.to_str().unwrap()]);
    assert!(run(&args, &[]).status.success());
    refused(
        &[&p0, &scene, &p2],
        &[
            "scene.cpart",
            "does not belong with",
            "its scene differs",
            "glass-sphere",
        ],
    );
    let seed = other("seed", &["--seed", "5"]);
    refused(
        &[&p0, &seed, &p2],
        &["seed.cpart", "its seed differs", "seed: 5"],
    );
    let sampler = other("sampler", &["--sampler", "independent"]);
    refused(
        &[&p0, &sampler, &p2],
        &["sampler.cpart", "its options differs", "Independent"],
    );
    let size = d.join("size.cpart");
    let mut args: Vec<&str> = RENDER
        .iter()
        .map(|a| if *a == "24" { "30" } else { a })
        .collect();
    args.extend_from_slice(&["--shard", "1/3", "-o", size.to_str().unwrap()]);
    assert!(run(&args, &[]).status.success());
    refused(
        &[&p0, &size, &p2],
        &["size.cpart", "its image size differs", "32x30"],
    );
    // Another caustica version: the manifest rewritten (a valid file otherwise).
    let bytes = std::fs::read(&p1).unwrap();
    let mut part = Part::decode(&bytes, "p1").unwrap();
    part.manifest.fingerprint =
        part.manifest
            .fingerprint
            .replacen("caustica ", "caustica 9.9.9-", 1);
    let version = d.join("version.cpart");
    std::fs::write(&version, part.to_bytes()).unwrap();
    refused(
        &[&p0, &version, &p2],
        &["version.cpart", "caustica version"],
    );
    // Corrupted and truncated files.
    let mut flipped = bytes.clone();
    let at = flipped.len() / 2;
    flipped[at] ^= 0x20;
    let corrupt = d.join("corrupt.cpart");
    std::fs::write(&corrupt, &flipped).unwrap();
    refused(&[&p0, &corrupt, &p2], &["corrupt.cpart", "corrupted"]);
    let truncated = d.join("truncated.cpart");
    std::fs::write(&truncated, &bytes[..bytes.len() - 100]).unwrap();
    refused(&[&p0, &truncated, &p2], &["truncated.cpart", "truncated"]);
    let image = d.join("image.cpart");
    std::fs::write(&image, b"not a part").unwrap();
    refused(&[&image], &["image.cpart", "not a caustica partial result"]);
    // And the three good parts still merge.
    let o = merge(&[&p0, &p1, &p2], &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn bad_shard_arguments_fail_cleanly() {
    let d = dir("bad");
    let o = |arg: &str, env: &[(&str, &str)]| {
        let mut args = RENDER.to_vec();
        let out = d.join("p/");
        args.extend_from_slice(&["--shard", arg, "-o", out.to_str().unwrap()]);
        run(&args, env)
    };
    assert_clean_failure(&o("5/4", &[]), &["--shard 5/4", "0 to 3"]);
    assert_clean_failure(&o("0/0", &[]), &["N >= 1"]);
    assert_clean_failure(&o("-1/4", &[]), &["index I"]);
    assert_clean_failure(
        &o("/4", &[]),
        &["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"],
    );
    assert_clean_failure(&o("/4", &[("JOB_COMPLETION_INDEX", "4")]), &["0 to 3"]);
    // A shard writes a partial result, not an image.
    let mut args = RENDER.to_vec();
    args.extend_from_slice(&["--shard", "0/2", "-o", "x.exr"]);
    assert_clean_failure(&run(&args, &[]), &[".cpart file or a directory"]);
    let mut args = RENDER.to_vec();
    args.extend_from_slice(&["--shard", "0/2", "--png", "x.png"]);
    assert_clean_failure(&run(&args, &[]), &["--png does not apply"]);
    // Methods that cannot be split say which can.
    let args = [
        "render",
        "--integrator",
        "sppm",
        "--shard",
        "0/2",
        "-o",
        d.to_str().unwrap(),
    ];
    assert_clean_failure(&run(&args, &[]), &["cannot be sharded exactly", "pppm"]);
    assert_clean_failure(
        &merge(&[&d.join("none.cpart")], &d.join("o.exr"), &[]),
        &["none.cpart"],
    );
}
