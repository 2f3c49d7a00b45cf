"""Does plastic flattening raise the measured-scan pull-off?  The AFM probe with a hardness cap.

The case of ``examples/pulloff_afm_park.toml`` (thesis Paper C, vacuum state): a smooth SiO2
sphere (R = 2.5 um) on a 0.25 um spot of a measured Si topography, Dugdale adhesion of
88 mJ/m^2, unloaded from a preload.  Paper C's model under-predicts the measured vacuum
pull-off; the asperity tips of the elastic solution carry about 10 GPa, near the hardness of
the bodies, so whether yielding tips (flattened, adhering over a larger area afterwards) close
part of the gap is a fair question.

Hardness values (indentation hardness, Berkovich nanoindentation; inputs of this study, not
properties the code knows):

* Si (100): about 11-12 GPa (Bhushan and Li, J. Mater. Res. 12, 1997; Pharr et al., 1989
  report 11-12 GPa); 11.5 GPa here, on the substrate;
* fused silica: about 9 GPa (Oliver and Pharr, J. Mater. Res. 7, 1992, their calibration
  material: 8.8-9.5 GPa); 9 GPa here, on the SiO2 probe.

The cap model uses the softer surface's hardness (9 GPa when the probe has one).  Each case
runs the pull-off kind with ``load.grid_levels`` (the spot on 64^2, then 2 and 4 times finer,
the scan interpolated bilinearly below its pixels), at the example's 100 nN preload and at ten
times it.

    python studies/afm_hardness.py [--levels 2] [--out results/afm_hardness.csv]
"""

from __future__ import annotations

import argparse
import csv
import time
import tomllib
import warnings
from pathlib import Path

from tribobem.scenario import parse_scenario, run_scenario

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "pulloff_afm_park.toml"

#: (label, body1 hardness, body2 hardness)
HARDNESS = (("elastic", None, None), ("Si substrate 11.5 GPa", "11.5 GPa", None),
            ("Si 11.5 GPa + SiO2 probe 9 GPa", "11.5 GPa", "9 GPa"))
PRELOADS = ("100 nN", "1 uN")


def run_case(preload: str, h1, h2, levels: int) -> dict:
    """One pull-off of the example's spot; returns the finest level's numbers and every level's pull-off."""
    data = tomllib.loads(EXAMPLE.read_text())
    data.pop("expected", None)
    data["load"]["preload"] = preload
    data["load"]["grid_levels"] = levels
    if h1:
        data["body1"]["hardness"] = h1
    if h2:
        data["body2"]["hardness"] = h2
    t = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = run_scenario(parse_scenario(data, source="afm_hardness"), outdir=None, progress=False,
                           base_dir=EXAMPLE.parent)
    summary = res.summary
    run = summary["run"] if "run" in summary else summary
    lv = run.get("grid_levels") or {}
    levels = lv.get("levels", [])
    last = levels[-1] if levels else {}
    return {"pull_off_levels": [x["pull_off_force"] for x in levels],
            "pull_off": last.get("pull_off_force", run.get("pull_off_force")), "change": lv.get("change"),
            "cpu_s": time.process_time() - t, "n": last.get("n"),
            "max_pressure": last.get("preload_max_pressure"),
            "plastic_area": last.get("preload_plastic_area", 0.0),
            "plastic_depth": last.get("preload_max_plastic_displacement", 0.0)}


def main(argv=None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--levels", type=int, default=2, help="grid levels above 64^2 (default 2: 64, 128, 256)")
    ap.add_argument("--out", type=Path, default=None, help="also write the table as CSV")
    args = ap.parse_args(argv)
    rows = []
    print("| preload | hardness | pull-off per level (nN) | change last two | finest: p max at preload (GPa) "
          "| A plastic (nm^2) | plastic depth (nm) | CPU s |")
    print("|---|---|---|---|---|---|---|---|")
    for preload in PRELOADS:
        for label, h1, h2 in HARDNESS:
            r = run_case(preload, h1, h2, args.levels)
            r.update(preload=preload, hardness=label)
            rows.append(r)
            lv = ", ".join(f"{1e9 * f:.2f}" for f in r["pull_off_levels"])
            ch = f"{100 * r['change']:+.1f} %" if r["change"] is not None else ""
            print(f"| {preload} | {label} | {lv} | {ch} | {1e-9 * r['max_pressure']:.2f} | "
                  f"{1e18 * r['plastic_area']:.0f} | {1e9 * r['plastic_depth']:.3f} | {r['cpu_s']:.0f} |", flush=True)
    if args.out is not None:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        with args.out.open("w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=[k for k in rows[0] if k != "pull_off_levels"])
            w.writeheader()
            for r in rows:
                w.writerow({k: v for k, v in r.items() if k != "pull_off_levels"})
    return rows


if __name__ == "__main__":
    main()
