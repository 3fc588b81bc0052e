//! `render --shard I/N`: which shard this process renders, where its partial result goes, and
//! the hash that ties the parts of one render together.

use anyhow::{Context, Result, bail};
use caustica_render::Shard;
use caustica_render::partial::{FNV_OFFSET, fnv1a};
use std::path::{Path, PathBuf};

/// The environment variables an array job sets to a task's index, in the order they are read
/// when `--shard /N` leaves the index out: Slurm job arrays (`sbatch --array=0-(N-1)`: the task
/// id is the shard index, so a resubmitted subset such as `--array=3,5` renders shards 3 and 5)
/// and Kubernetes Indexed Jobs.
pub const INDEX_VARIABLES: [&str; 2] = ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"];

/// Parses `--shard I/N` (or `/N`, the index read by `env` from [`INDEX_VARIABLES`]).
pub fn parse_shard(text: &str, env: impl Fn(&str) -> Option<String>) -> Result<Shard> {
    let Some((i, n)) = text.split_once('/') else {
        bail!(
            "--shard expects I/N (shard I of N, 0 <= I < N) or /N (I from SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX), got '{text}'"
        );
    };
    let n: u32 = n.trim().parse().map_err(|_| {
        anyhow::anyhow!("--shard {text}: the shard count N must be a positive integer, got '{n}'")
    })?;
    let i: u32 = if i.trim().is_empty() {
        index_from_env(&env).with_context(|| format!("--shard {text}"))?
    } else {
        i.trim().parse().map_err(|_| {
            anyhow::anyhow!(
                "--shard {text}: the shard index I must be a non-negative integer, got '{i}'"
            )
        })?
    };
    Shard::new(i, n).map_err(anyhow::Error::msg)
}

/// The task index an array job gave this process.
fn index_from_env(env: &impl Fn(&str) -> Option<String>) -> Result<u32> {
    let int = |var: &str| -> Result<Option<u32>> {
        match env(var) {
            None => Ok(None),
            Some(v) => v
                .trim()
                .parse()
                .map(Some)
                .map_err(|_| anyhow::anyhow!("{var}={v} is not a non-negative integer")),
        }
    };
    if let Some(id) = int("SLURM_ARRAY_TASK_ID")? {
        return Ok(id);
    }
    if let Some(i) = int("JOB_COMPLETION_INDEX")? {
        return Ok(i);
    }
    bail!(
        "the shard index is not given and none of {} is set (give --shard I/N)",
        INDEX_VARIABLES.join(", ")
    )
}

/// Where shard `shard` writes its partial result for `-o output`: `output` itself if it ends in
/// `.cpart`, `output/shard-IIII-of-NNNN.cpart` if it is a directory (existing, or written with
/// a trailing `/`), that name in the working directory without `-o`.
pub fn part_path(output: Option<&Path>, shard: Shard) -> Result<PathBuf> {
    let name = format!("shard-{:04}-of-{:04}.cpart", shard.index(), shard.count());
    let Some(out) = output else {
        return Ok(PathBuf::from(name));
    };
    let text = out.to_string_lossy();
    if text.ends_with('/') || out.is_dir() {
        return Ok(out.join(name));
    }
    if out.extension().and_then(|e| e.to_str()) == Some("cpart") {
        return Ok(out.to_path_buf());
    }
    bail!(
        "with --shard, -o names the partial result: a .cpart file or a directory (got {}); `caustica merge` writes the image",
        out.display()
    )
}

/// What identifies the scene of a render beyond its name and counts (which the render's
/// fingerprint holds): the bytes of its file (or the built-in name) and `changes`, the
/// command-line settings that alter it (-D values, size, shutter, spectral mode), as 16 hex
/// digits. Files the scene includes (meshes, volumes) are not read: their counts are in the
/// fingerprint.
pub fn scene_hash(scene: Option<&str>, changes: &str) -> Result<String> {
    let mut h = FNV_OFFSET;
    match scene {
        Some(s) if Path::new(s).is_file() => {
            let bytes = std::fs::read(s).with_context(|| format!("cannot read scene {s}"))?;
            h = fnv1a(h, b"file\0");
            h = fnv1a(h, &bytes);
        }
        Some(name) => h = fnv1a(fnv1a(h, b"builtin\0"), name.as_bytes()),
        None => h = fnv1a(h, b"default\0"),
    }
    h = fnv1a(fnv1a(h, b"\0"), changes.as_bytes());
    Ok(format!("{h:016x}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env(vars: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> {
        let v: Vec<(String, String)> = vars
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        move |k| v.iter().find(|(n, _)| n == k).map(|(_, x)| x.clone())
    }

    #[test]
    fn the_index_comes_from_the_argument_or_the_array_job() {
        let none = env(&[]);
        assert_eq!(
            parse_shard("3/8", &none).unwrap(),
            Shard::new(3, 8).unwrap()
        );
        // The task id is the index, also in a resubmitted subset (--array=3,5: MIN is 3).
        let slurm = env(&[("SLURM_ARRAY_TASK_ID", "5"), ("SLURM_ARRAY_TASK_MIN", "3")]);
        assert_eq!(
            parse_shard("/8", &slurm).unwrap(),
            Shard::new(5, 8).unwrap()
        );
        let k8s = env(&[("JOB_COMPLETION_INDEX", "7")]);
        assert_eq!(parse_shard("/8", &k8s).unwrap(), Shard::new(7, 8).unwrap());
        // Given explicitly, the environment is not read.
        assert_eq!(parse_shard("2/8", &k8s).unwrap().index(), 2);
    }

    #[test]
    fn bad_shards_are_refused_with_a_reason() {
        let none = env(&[]);
        for (arg, says) in [
            ("5/4", "0 to 3"),
            ("4/4", "0 to 3"),
            ("0/0", "N >= 1"),
            ("x/4", "index I"),
            ("1/-2", "count N"),
            ("3", "expects I/N"),
            ("/4", "SLURM_ARRAY_TASK_ID"),
        ] {
            let e = format!("{:#}", parse_shard(arg, &none).unwrap_err());
            assert!(e.contains(says), "{arg}: {e}");
        }
        let e = format!(
            "{:#}",
            parse_shard("/4", env(&[("JOB_COMPLETION_INDEX", "4")])).unwrap_err()
        );
        assert!(e.contains("0 to 3"), "{e}");
        let e = format!(
            "{:#}",
            parse_shard("/4", env(&[("SLURM_ARRAY_TASK_ID", "a")])).unwrap_err()
        );
        assert!(e.contains("SLURM_ARRAY_TASK_ID=a"), "{e}");
    }

    #[test]
    fn parts_are_named_by_shard() {
        let s = Shard::new(3, 12).unwrap();
        assert_eq!(
            part_path(Some(Path::new("parts/")), s).unwrap(),
            PathBuf::from("parts/shard-0003-of-0012.cpart")
        );
        assert_eq!(
            part_path(Some(Path::new("a/b.cpart")), s).unwrap(),
            PathBuf::from("a/b.cpart")
        );
        assert_eq!(
            part_path(None, s).unwrap(),
            PathBuf::from("shard-0003-of-0012.cpart")
        );
        assert!(part_path(Some(Path::new("out.exr")), s).is_err());
    }

    #[test]
    fn the_scene_hash_sees_the_source_and_the_changes() {
        let a = scene_hash(Some("cornell-box"), "").unwrap();
        assert_eq!(a, scene_hash(Some("cornell-box"), "").unwrap());
        assert_ne!(a, scene_hash(Some("glass-sphere"), "").unwrap());
        assert_ne!(a, scene_hash(Some("cornell-box"), "width 64").unwrap());
        assert_ne!(a, scene_hash(None, "").unwrap());
    }
}
