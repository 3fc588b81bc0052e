#!/usr/bin/env python3
"""Checks the Kubernetes manifests of this folder and runs their pods' commands on this machine.

    local_pod.py check MANIFEST.yaml --set VAR=VALUE ...
    local_pod.py run MANIFEST.yaml --set VAR=VALUE ... [--index I] [--map /data=DIR ...] [--env K=V ...]

Both fill the ${VAR} placeholders as `envsubst` does (every placeholder must be given).
`check` validates the Jobs against the Kubernetes API's own models when the `kubernetes` Python
client is installed (a misspelt or misplaced field is an error, not silently dropped as by the
API server's non-strict decoding), and checks what the shards rely on: an Indexed Job whose
completions equal the container's SHARDS, per-index retries with restartPolicy Never, the parts
on a mounted volume and the scripts from the mounted ConfigMap.
`run` runs the first container's command as a pod would: its env (with the CPU limit of a
resourceFieldRef), JOB_COMPLETION_INDEX=I and the pod hostname for an Indexed Job, paths of mounted
volumes mapped to local directories (--map MOUNT=DIR), and PATH and --env from here. Exits with the
command's status. Used by test_engines.sh; no cluster needed.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import string
import subprocess
import sys
from pathlib import Path

import yaml

PLACEHOLDER = re.compile(r"\$\{([A-Za-z_][A-Za-z0-9_]*)\}")


def fill(text: str, values: dict[str, str]) -> str:
    missing = sorted({m for m in PLACEHOLDER.findall(text) if m not in values})
    if missing:
        sys.exit(f"local_pod: placeholders without a value: {', '.join(missing)} (--set VAR=VALUE)")
    return string.Template(text).safe_substitute(values)


def load(path: Path, values: dict[str, str]) -> list[dict]:
    return [d for d in yaml.safe_load_all(fill(path.read_text(), values)) if d]


def dropped_fields(original, back, where=""):
    """Fields of `original` that a round trip through the API models lost (unknown to the API)."""
    out = []
    if isinstance(original, dict):
        for k, v in original.items():
            if not isinstance(back, dict) or k not in back:
                out.append(f"{where}.{k}")
            else:
                out += dropped_fields(v, back[k], f"{where}.{k}")
    elif isinstance(original, list):
        for i, v in enumerate(original):
            out += dropped_fields(v, back[i] if isinstance(back, list) and i < len(back) else None, f"{where}[{i}]")
    return out


def validate_with_models(doc: dict) -> list[str]:
    try:
        from kubernetes.client import ApiClient  # type: ignore
    except ImportError:
        return []
    kind = {"Job": "V1Job", "PersistentVolumeClaim": "V1PersistentVolumeClaim"}.get(doc.get("kind", ""))
    if kind is None:
        return [f"no model for kind {doc.get('kind')!r}"]

    class Response:  # what ApiClient.deserialize reads before client 32 (later: the text itself)
        data = json.dumps(doc)

    api = ApiClient()
    try:
        try:
            obj = api.deserialize(json.dumps(doc), kind, "application/json")
        except TypeError:
            obj = api.deserialize(Response(), kind)
    except (ValueError, TypeError) as e:
        return [f"{kind}: {e}"]
    back = api.sanitize_for_serialization(obj)
    return [f"{kind}: unknown field {f}" for f in dropped_fields(doc, back)]


def container(doc: dict) -> dict:
    return doc["spec"]["template"]["spec"]["containers"][0]


def env_of(doc: dict) -> dict[str, str]:
    c = container(doc)
    env = {}
    for e in c.get("env", []):
        if "value" in e:
            env[e["name"]] = str(e["value"])
        elif "valueFrom" in e and "resourceFieldRef" in e["valueFrom"]:
            ref = e["valueFrom"]["resourceFieldRef"]
            kind, _, res = ref["resource"].partition(".")
            qty = c.get("resources", {}).get(kind, {}).get(res)
            if res == "cpu" and qty is not None:
                q = str(qty)
                cores = float(q[:-1]) / 1000 if q.endswith("m") else float(q)
                env[e["name"]] = str(math.ceil(cores / float(ref.get("divisor", 1))))
            elif qty is not None:
                env[e["name"]] = str(qty)
    return env


def check(docs: list[dict]) -> list[str]:
    problems = []
    for doc in docs:
        problems += validate_with_models(doc)
        if doc.get("kind") != "Job":
            continue
        spec = doc["spec"]
        pod = spec["template"]["spec"]
        name = doc["metadata"]["name"]
        c = container(doc)
        env = env_of(doc)
        mounts = {m["name"]: m["mountPath"] for m in c.get("volumeMounts", [])}
        volumes = {v["name"]: v for v in pod.get("volumes", [])}
        if pod.get("restartPolicy") != "Never":
            problems.append(f"{name}: restartPolicy must be Never (a retry is a new pod)")
        for m in mounts:
            if m not in volumes:
                problems.append(f"{name}: volumeMount {m} has no volume")
        script = next((a for a in c.get("command", []) + c.get("args", []) if a.endswith(".sh")), None)
        cm_paths = [mounts[n] for n, v in volumes.items() if "configMap" in v and n in mounts]
        if script is None or not any(script.startswith(p + "/") for p in cm_paths):
            problems.append(f"{name}: the command's script {script} is not in a mounted ConfigMap")
        pvc_paths = [mounts[n] for n, v in volumes.items() if "persistentVolumeClaim" in v and n in mounts]
        parts = env.get("PARTS_DIR", "")
        if not any(parts.startswith(p + "/") for p in pvc_paths):
            problems.append(f"{name}: PARTS_DIR {parts!r} is not on a mounted PersistentVolumeClaim")
        if spec.get("completionMode") == "Indexed":
            if str(spec.get("completions")) != env.get("SHARDS"):
                problems.append(
                    f"{name}: completions {spec.get('completions')} differ from the container's SHARDS {env.get('SHARDS')}"
                )
            if "backoffLimitPerIndex" not in spec:
                problems.append(f"{name}: no backoffLimitPerIndex (per-index retries)")
            if "--shard" in " ".join(c.get("command", []) + c.get("args", [])):
                problems.append(f"{name}: the shard index must come from JOB_COMPLETION_INDEX, not a fixed --shard")
    return problems


def run(doc: dict, index: int | None, maps: list[tuple[str, str]], extra_env: dict[str, str]) -> int:
    def local(s: str) -> str:
        for mount, directory in maps:
            if s == mount or s.startswith(mount + "/"):
                return directory + s[len(mount) :]
        return s

    c = container(doc)
    env = {k: local(v) for k, v in env_of(doc).items()}
    env["PATH"] = os.environ.get("PATH", "/usr/bin:/bin")
    env["HOME"] = os.environ.get("HOME", "/root")
    name = doc["metadata"]["name"]
    if doc["spec"].get("completionMode") == "Indexed":
        if index is None:
            sys.exit("local_pod: an Indexed Job's pod needs --index")
        env["JOB_COMPLETION_INDEX"] = str(index)
        env["HOSTNAME"] = f"{name}-{index}"
    else:
        env["HOSTNAME"] = f"{name}-local"
    env.update(extra_env)
    cmd = [local(a) for a in c.get("command", []) + c.get("args", [])]
    return subprocess.run(cmd, env=env, check=False).returncode


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("mode", choices=["check", "run"])
    p.add_argument("manifest", type=Path)
    p.add_argument("--set", action="append", default=[], metavar="VAR=VALUE")
    p.add_argument("--index", type=int)
    p.add_argument("--map", action="append", default=[], metavar="MOUNT=DIR")
    p.add_argument("--env", action="append", default=[], metavar="K=V")
    a = p.parse_args(argv)
    values = dict(s.split("=", 1) for s in a.set)
    docs = load(a.manifest, values)
    if a.mode == "check":
        problems = check(docs)
        for pr in problems:
            print(f"{a.manifest.name}: {pr}", file=sys.stderr)
        try:
            import kubernetes  # type: ignore # noqa: F401

            how = "against the kubernetes client's API models"
        except ImportError:
            how = "without the kubernetes client (structure only)"
        if not problems:
            print(f"{a.manifest.name}: ok ({how})")
        return 1 if problems else 0
    jobs = [d for d in docs if d.get("kind") == "Job"]
    maps = [tuple(m.split("=", 1)) for m in a.map]
    return run(jobs[0], a.index, maps, dict(e.split("=", 1) for e in a.env))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
