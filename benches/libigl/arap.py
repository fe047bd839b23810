"""libigl's ARAP on the drag suite of issue 10 (benchmark only, not in CI).

Reads every case that `node benches/suite.mjs` wrote to target/suite/<case>.json (the mesh,
the pin vertices and every update's targets), runs libigl's ARAP (`igl.arap_precomputation`
+ `igl.arap_solve`, the default energy, which for 2D triangles is ARAP_ENERGY_TYPE_ELEMENTS:
one rotation per triangle, cotangent weights) with `max_iter` local/global iterations per
update, warm-started from the previous update's result, the pin vertices held exactly at
their targets (hard constraints), and writes for each case

  target/suite/libigl/<case>.f64    every update's positions, float64, [x0, y0, x1, …] per update
  target/suite/libigl/<case>.json   vertexCount, updates, iterations, version, per-update ms, …

which benches/suite.mjs measures with puppet.qualityOf (the same code as bunraku's rows).

  python benches/libigl/arap.py [--iterations 10] [--only twist-180,disc-coarse]
"""

import argparse
import json
import pathlib
import sys
import time
from importlib.metadata import version

import igl
import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

ROOT = pathlib.Path(__file__).resolve().parents[2]
SUITE = ROOT / "target" / "suite"


def signed_areas(x, f):
    a, b, c = x[f[:, 0]], x[f[:, 1]], x[f[:, 2]]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def run(path, iterations):
    case = json.loads(path.read_text())
    v = np.asarray(case["vertices"], dtype=np.float64).reshape(-1, 2)
    f = np.asarray(case["triangles"], dtype=np.int64).reshape(-1, 3)
    b = np.asarray(case["pinVertices"], dtype=np.int32)
    frames = [np.asarray(t, dtype=np.float64).reshape(-1, 2) for t in case["frames"]]

    # A connected component with no pin makes libigl's system singular; bunraku leaves such
    # a component at rest (docs/conventions.md, 8), so hold all its vertices at rest here.
    n = v.shape[0]
    edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    free = np.setdiff1d(np.unique(label), label[b])
    still = np.flatnonzero(np.isin(label, free)).astype(np.int32)
    if len(still):
        b = np.concatenate([b, still])
        frames = [np.vstack([t, v[still]]) for t in frames]

    data = igl.ARAPData()
    data.max_iter = iterations
    t0 = time.perf_counter()
    igl.arap_precomputation(v, f, 2, b, data)
    precompute_ms = 1e3 * (time.perf_counter() - t0)

    u = v.copy()
    out = np.empty((len(frames), v.shape[0], 2))
    ms = []
    for k, bc in enumerate(frames):
        t = time.perf_counter()
        u = igl.arap_solve(bc, data, u)
        ms.append(1e3 * (time.perf_counter() - t))
        out[k] = u
    flipped = [int(np.sum(signed_areas(x, f) <= 0)) for x in out]

    dest = SUITE / "libigl"
    dest.mkdir(parents=True, exist_ok=True)
    out.astype("<f8").tofile(dest / f"{case['name']}.f64")
    meta = {
        "name": case["name"],
        "fingerprint": case["fingerprint"],
        "vertexCount": int(v.shape[0]),
        "updates": len(frames),
        "iterations": iterations,
        "energy": "ARAP_ENERGY_TYPE_DEFAULT (ELEMENTS for 2D triangles)",
        "version": version("libigl"),
        "numpy": np.__version__,
        "python": sys.version.split()[0],
        "precomputeMs": precompute_ms,
        "ms": ms,
        "maxFlipped": max(flipped),
        "restingVertices": int(len(still)),
    }
    (dest / f"{case['name']}.json").write_text(json.dumps(meta))
    print(
        f"{case['name']:>20}: {v.shape[0]:6d} vertices, precompute {precompute_ms:7.1f} ms, "
        f"update median {np.median(ms):7.2f} ms, max flipped {max(flipped)}"
        + (f" ({len(still)} vertices of unpinned components held at rest)" if len(still) else "")
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--iterations", type=int, default=10)
    parser.add_argument("--only", default="")
    args = parser.parse_args()
    only = [n for n in args.only.split(",") if n]
    paths = sorted(p for p in SUITE.glob("*.json") if not only or p.stem in only)
    if not paths:
        sys.exit("no cases in target/suite/: run `node benches/suite.mjs` first")
    print(f"libigl {version('libigl')}, ARAP with {args.iterations} iterations per update, warm-started, hard pins")
    for p in paths:
        run(p, args.iterations)


if __name__ == "__main__":
    main()
