"""Analyse a scanned stone loaded with trimesh and plot n(ν), the paper's Fig. 10B.

    pip install ./python trimesh matplotlib
    python examples/analyze_with_trimesh.py [MESH] [-o n_nu.png]

MESH defaults to the scanned quarry stone E34 in the repository's data/meshes.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import trimesh  # noqa: E402

import rocking_stones as rs  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
DEFAULT = REPO / "data" / "meshes" / "stone_quarry_ibois_E34_lowres_bin.ply"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mesh", nargs="?", default=DEFAULT, type=Path)
    ap.add_argument("-o", "--output", default=Path("n_nu.png"), type=Path)
    args = ap.parse_args()

    # Any trimesh.Trimesh (or a (vertices, faces) pair of arrays) goes in as it is. trimesh's
    # default processing merges vertices closer than 1e-8; process=False keeps the scan as stored.
    mesh = trimesh.load(args.mesh, force="mesh", process=False)
    a = rs.analyze(mesh, name=args.mesh.name)
    print(a.summary())

    s = a.staircase  # one row per constant step of N(ν): nu_lo, nu_hi, stable, unstable, saddle, n
    # The steps tile [0, v_max): n(ν) = N(ν)/N(0) as stairs in log ν (the first step starts at
    # ν = 0, which a log axis cannot show: it is drawn from a decade below the first cancellation).
    edges = np.append(s["nu_lo"], s["nu_hi"][-1])
    edges[0] = edges[1] / 10

    fig, ax = plt.subplots(figsize=(7, 4.2), dpi=150)
    ax.stairs(s["n"], edges, baseline=None, color="k", lw=1.5, label="n(ν) = N(ν) / N(0)")
    if a.plateau is not None:
        p = a.plateau
        ax.axvspan(p["nu_lo"], p["nu_hi"], color="tab:orange", alpha=0.2,
                   label=f"plateau: {p['decades']:.2f} decades, {'clear' if p['clear'] else 'not clear'}")
    S, U, H = a.macro
    ax.axvline(a.nu, color="tab:red", ls="--", lw=1, label=f"macro ν = {a.nu:.2e}: S={S} U={U} H={H}")
    ax.axvline(rs.PAPER_NU, color="tab:blue", ls=":", lw=1, label="paper's hand experimenter ν = 0.0035")
    ax.set_xscale("log")
    ax.set_xlabel("ν")
    ax.set_ylabel("n(ν)")
    S0, U0, H0 = a.micro
    ax.set_title(f"{args.mesh.name}\nmicro S={S0} U={U0} H={H0}, {len(a.rocking['index'])} rocking equilibria", fontsize=10)
    ax.set_ylim(0, 1.05)
    ax.legend(fontsize=8, loc="lower left")
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.output)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
