"""Reading `caustica sweep` results (sweep.csv: value,rmse,rel_mse,mise,ssim,seconds), shared by
the case-study summarisers."""
import csv


def rows(path):
    """The rows of a sweep.csv, numbers as floats; `value` kept as written (e.g. "0.05")."""
    with open(path) as f:
        return [
            {k: (v if k == "value" else float(v)) for k, v in r.items()}
            for r in csv.DictReader(f)
        ]


def best(rs, metric):
    """The row optimal for `metric`: smallest RMSE / MISE / relative MSE, largest SSIM."""
    pick = min if metric != "ssim" else max
    return pick(rs, key=lambda r: r[metric])
