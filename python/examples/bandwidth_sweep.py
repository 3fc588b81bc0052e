"""Sweep pds's smoothing on the water wave's caustic and plot the RMSE against a light-tracer
reference (docs/python.md). Writes docs/results/python/bandwidth-sweep.{png,csv}.

    target/py-venv/bin/python python/examples/bandwidth_sweep.py
"""

import pathlib
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import caustica

out = pathlib.Path(__file__).resolve().parents[2] / "docs" / "results" / "python"
out.mkdir(parents=True, exist_ok=True)

scene = caustica.load("water-wave")
common = dict(width=128, caustics_only=True, seed=1)

# The reference: the light tracer, unbiased for the caustic (L S+ D E paths), 60 s.
t = time.time()
reference, notes = caustica.render(scene, integrator="lighttrace", time=60.0, **common)
print(f"reference: {notes['light_paths']} light paths in {time.time() - t:.1f} s")
caustica.write(out / "reference.exr", reference)

rows = []
for s in [0.5, 1, 2, 4, 8, 16, 32, 64]:
    image, notes = caustica.render(scene, integrator="pds", photons=20_000, spp=4,
                                   smoothing=s, **common)
    m = caustica.compare(image, reference)
    rows.append((s, m["rmse"], m["ssim"], notes["seconds"]))
    print(f"smoothing {s:5}: RMSE {m['rmse']:.5f}  SSIM {m['ssim']:.4f}  {notes['seconds']:.2f} s")

(out / "bandwidth-sweep.csv").write_text(
    "smoothing,rmse,ssim,seconds\n" + "".join(f"{s},{r:.6f},{q:.5f},{t:.3f}\n" for s, r, q, t in rows))
fig, ax = plt.subplots(figsize=(5, 3.2))
ax.loglog([r[0] for r in rows], [r[1] for r in rows], "o-")
ax.set_xlabel("smoothing s (pds)")
ax.set_ylabel("RMSE against the light tracer")
ax.set_title("water wave caustic, 20 000 photons")
ax.grid(True, which="both", alpha=0.3)
fig.tight_layout()
fig.savefig(out / "bandwidth-sweep.png", dpi=120)
