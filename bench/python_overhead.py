"""The Python package's overhead against the command line on small renders (issue 25's target:
within 5 %). Run by bench/python_overhead.sh; see docs/performance.md.

For each case, alternating ROUNDS times:
  cli      the whole `caustica render ... -q -o X.exr` process (scene load, render, EXR write),
  py-call  caustica.load + caustica.render + caustica.write in this (warm) interpreter,
  py-proc  a fresh `python -c "import caustica; ..."` process doing the same (interpreter
           start, NumPy import included).
Prints medians, ratios to cli and the spread (min..max of the per-round ratios), and checks
that the images are bit-identical.
"""

import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import caustica

CLI = os.environ["CAUSTICA"]
ROUNDS = int(os.environ.get("ROUNDS", "7"))
CASES = [
    ("path 64x64, 16 spp", "caustic-box", dict(integrator="path", spp=16, width=64)),
    ("pds water wave 128, 20k photons", "water-wave",
     dict(integrator="pds", photons=20_000, spp=4, width=128)),
    ("path 16x16, 1 spp (start-up)", "caustic-box", dict(integrator="path", spp=1, width=16)),
]


def cli_args(kwargs):
    args = []
    for k, v in kwargs.items():
        args += [f"--{k.replace('_', '-')}", str(v)]
    return args


def main():
    tmp = tempfile.mkdtemp()
    print(f"caustica {CLI}; python {sys.version.split()[0]}; {ROUNDS} rounds", flush=True)
    print(f"{'case':36} {'cli s':>8} {'py-call s':>10} {'ratio':>7} {'spread':>15} "
          f"{'py-proc s':>10} {'ratio':>7} {'spread':>15} {'bits'}")
    for name, scene, kw in CASES:
        cli_t, call_t, proc_t = [], [], []
        cli_out, py_out, proc_out = (os.path.join(tmp, f) for f in ("c.exr", "p.exr", "q.exr"))
        script = (f"import caustica; img, _ = caustica.render(caustica.load({scene!r}), **{kw!r}); "
                  f"caustica.write({proc_out!r}, img)")
        for _ in range(ROUNDS):
            t = time.perf_counter()
            subprocess.run([CLI, "render", scene, *cli_args(kw), "-q", "-o", cli_out], check=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            cli_t.append(time.perf_counter() - t)
            t = time.perf_counter()
            img, _ = caustica.render(caustica.load(scene), **kw)
            caustica.write(py_out, img)
            call_t.append(time.perf_counter() - t)
            t = time.perf_counter()
            subprocess.run([sys.executable, "-c", script], check=True, stderr=subprocess.DEVNULL)
            proc_t.append(time.perf_counter() - t)
        same = all(np.array_equal(caustica.read(cli_out).view(np.uint32), caustica.read(p).view(np.uint32))
                   for p in (py_out, proc_out))
        r1 = [a / b for a, b in zip(call_t, cli_t)]
        r2 = [a / b for a, b in zip(proc_t, cli_t)]
        med = statistics.median
        print(f"{name:36} {med(cli_t):8.3f} {med(call_t):10.3f} {med(r1):7.3f} "
              f"{min(r1):7.3f}..{max(r1):6.3f} {med(proc_t):10.3f} {med(r2):7.3f} "
              f"{min(r2):7.3f}..{max(r2):6.3f} {'identical' if same else 'DIFFERENT'}", flush=True)


if __name__ == "__main__":
    main()
