#!/usr/bin/env python3
"""Measures the shadow denoisers on the scene lab's built-in scenes and prints a Markdown table.

For every scene, size and method it runs `nrd-sample` (JSON report into --out, reused when it
exists, so an interrupted batch resumes) and tabulates the relMSE ratio noisy / denoised, FLIP
noisy -> denoised, the `--bounds` oracle's ratio and whether the output meets do-no-harm (relMSE
and FLIP no higher than the input's) and, on moving scenes, half the oracle's ratio.

  shadow_table.py --sample build/bin/nrd-sample --out shadow-runs --sizes 64 128 256 \
                  --methods SIGMA_SHADOW TILED_SHADOW --frames 40 --warmup 8 [--scenes static ...] \
                  [--seeds 1 2 3 4 5 6] [--jobs 8]

With --seeds every combination runs once per noise seed (`nrd-sample --seed`) and the table gives the
relMSE and FLIP of input, output and oracle summed over the seeds: one seed's ratio spreads by several
percent on the moving scenes (Shaders/TiledShadow/README.md, "Do no harm over several seeds").
"""
import argparse
import concurrent.futures
import json
import os
import subprocess
import sys

# Scenes whose camera, lights and objects do not move: no bound to approach (the oracle is a plain
# running mean there).
STILL_SCENES = {"static", "grazing_floor", "roughness_sweep", "sky", "thin_geometry"}


def builtin_scenes(root):
    folder = os.path.join(root, "Samples", "Scenes")
    return sorted(f[:-5] for f in os.listdir(folder) if f.endswith(".json"))


def run(args, scene, size, method, path, seed=None):
    if os.path.exists(path):
        return json.load(open(path))
    cmd = [args.sample, "--scene", os.path.join(args.scenes_dir, scene + ".json"), "--method", method, "--size", "%dx%d" % (size, size),
           "--frames", str(args.frames), "--warmup", str(args.warmup), "--truth-spp", str(args.truth_spp),
           "--out", os.path.join(args.out, "images"), "--json", path, "--quiet", "--bounds"]
    if seed is not None:
        cmd += ["--seed", str(seed)]
    result = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if result.returncode != 0:
        sys.exit("%s failed: %s" % (" ".join(cmd), result.stderr))
    return json.load(open(path))


def main():
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    p = argparse.ArgumentParser()
    p.add_argument("--sample", default=os.path.join(root, "build", "bin", "nrd-sample"))
    p.add_argument("--out", default="shadow-runs")
    p.add_argument("--sizes", type=int, nargs="+", default=[64, 128, 256])
    p.add_argument("--methods", nargs="+", default=["SIGMA_SHADOW", "TILED_SHADOW"])
    p.add_argument("--scenes", nargs="+", default=None)
    p.add_argument("--frames", type=int, default=24)
    p.add_argument("--warmup", type=int, default=8)
    p.add_argument("--truth-spp", type=int, default=32)
    p.add_argument("--scenes-dir", default=os.path.join(root, "Samples", "Scenes"))
    p.add_argument("--seeds", type=int, nargs="+", default=None, help="sum over these noise seeds (default: the scene's)")
    p.add_argument("--jobs", type=int, default=1, help="nrd-sample runs at once")
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    scenes = args.scenes or builtin_scenes(root)

    seeds = args.seeds or [None]

    def path_of(scene, size, method, seed):
        suffix = "" if seed is None else "-seed%d" % seed
        return os.path.join(args.out, "%s-%d-%s-%d%s.json" % (scene, size, method, args.frames, suffix))

    # All runs first (in parallel with --jobs), then the table from their reports.
    runs = [(scene, size, method, seed) for scene in scenes for size in args.sizes for method in args.methods for seed in seeds]
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(args.jobs, 1)) as pool:
        list(pool.map(lambda k: run(args, k[0], k[1], k[2], path_of(*k), k[3]), runs))

    title = "" if args.seeds is None else " (summed over seeds %s)" % ", ".join(str(s) for s in seeds)
    print("| scene | size | oracle ratio%s | " % title + " | ".join("%s ratio | FLIP in -> out | ok" % m for m in args.methods) + " |")
    print("|---|---|---|" + "---|---|---|" * len(args.methods))
    for scene in scenes:
        for size in args.sizes:
            cells = []
            oracle = None
            for method in args.methods:
                totals = {"relmse_noisy": 0.0, "relmse_denoised": 0.0, "flip_noisy": 0.0, "flip_denoised": 0.0, "oracle": 0.0}
                for seed in seeds:
                    r = run(args, scene, size, method, path_of(scene, size, method, seed), seed)["signals"]["shadow"]
                    for key in ("relmse_noisy", "relmse_denoised", "flip_noisy", "flip_denoised"):
                        totals[key] += r[key]
                    bound = r.get("bounds", {}).get("oracle_relmse", -1)
                    totals["oracle"] = totals["oracle"] + bound if bound > 0 and totals["oracle"] >= 0 else -1.0
                ratio = totals["relmse_noisy"] / max(totals["relmse_denoised"], 1e-12)
                if oracle is None and totals["oracle"] > 0:
                    oracle = totals["relmse_noisy"] / totals["oracle"]
                ok = totals["relmse_denoised"] <= totals["relmse_noisy"] and totals["flip_denoised"] <= totals["flip_noisy"]
                if scene not in STILL_SCENES and oracle is not None:
                    ok = ok and ratio >= 0.5 * oracle
                n = len(seeds)
                cells.append("%.2f | %.4f -> %.4f | %s" % (ratio, totals["flip_noisy"] / n, totals["flip_denoised"] / n, "yes" if ok else "**no**"))
            print("| %s | %d | %s | %s |" % (scene, size, "%.2f" % oracle if oracle else "", " | ".join(cells)), flush=True)


if __name__ == "__main__":
    main()
