#!/usr/bin/env python3
"""Measures the shadow denoisers on the scene lab's built-in scenes and prints a Markdown table.

For every scene, size and method it runs `nrd-sample` (JSON report into --out, reused when it
exists, so an interrupted batch resumes) and tabulates the relMSE ratio noisy / denoised, FLIP
noisy -> denoised, the `--bounds` oracle's ratio and whether the output meets do-no-harm (relMSE
and FLIP no higher than the input's) and, on moving scenes, half the oracle's ratio.

  shadow_table.py --sample build/bin/nrd-sample --out shadow-runs --sizes 64 128 256 \
                  --methods SIGMA_SHADOW TILED_SHADOW --frames 40 --warmup 8 [--scenes static ...]
"""
import argparse
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


def run(args, scene, size, method, path):
    if os.path.exists(path):
        return json.load(open(path))
    cmd = [args.sample, "--scene", os.path.join(args.scenes_dir, scene + ".json"), "--method", method, "--size", "%dx%d" % (size, size),
           "--frames", str(args.frames), "--warmup", str(args.warmup), "--truth-spp", str(args.truth_spp),
           "--out", os.path.join(args.out, "images"), "--json", path, "--quiet", "--bounds"]
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
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    scenes = args.scenes or builtin_scenes(root)

    print("| scene | size | oracle ratio | " + " | ".join("%s ratio | FLIP in -> out | ok" % m for m in args.methods) + " |")
    print("|---|---|---|" + "---|---|---|" * len(args.methods))
    for scene in scenes:
        for size in args.sizes:
            cells = []
            oracle = None
            for method in args.methods:
                path = os.path.join(args.out, "%s-%d-%s-%d.json" % (scene, size, method, args.frames))
                r = run(args, scene, size, method, path)["signals"]["shadow"]
                ratio = r["relmse_noisy"] / max(r["relmse_denoised"], 1e-12)
                if oracle is None and r.get("bounds", {}).get("oracle_relmse", -1) > 0:
                    oracle = r["relmse_noisy"] / r["bounds"]["oracle_relmse"]
                ok = r["relmse_denoised"] <= r["relmse_noisy"] and r["flip_denoised"] <= r["flip_noisy"]
                if scene not in STILL_SCENES and oracle is not None:
                    ok = ok and ratio >= 0.5 * oracle
                cells.append("%.2f | %.4f -> %.4f | %s" % (ratio, r["flip_noisy"], r["flip_denoised"], "yes" if ok else "**no**"))
            print("| %s | %d | %s | %s |" % (scene, size, "%.2f" % oracle if oracle else "", " | ".join(cells)), flush=True)


if __name__ == "__main__":
    main()
