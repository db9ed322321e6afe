#!/usr/bin/env python3
"""Quality of the BP method against low-discrepancy sampling on the four paper scenes.

For each scene at the paper's spp (ALGORITHM.md section 12) and each seed, renders
  LD at equal kept spp, LD at BP's traced spp (equal rays per pixel), LD at 64 spp on tire,
  BP (defaults, reconstructed), BP sampling only (its raw estimate), and the same two for
  BP --preset tuned,
and compares each with a high-spp LD reference: linear MSE, relative MSE and tone-mapped
MSE, averaged over the seeds (with the standard deviation). Prints a Markdown table.

Usage: scripts/bp_results.py [--penumbra build/penumbra] [--refs out/ref] [--ref-spp 2048]
                             [--seeds 3] [--scenes stairs,balls,tire,dragon] [--out FILE]
Missing references are rendered first (minutes per scene on 2 cores).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

PAPER_SPP = {"stairs": 16, "balls": 32, "tire": 16, "dragon": 16}


def run(cmd):
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("bp_results: command failed: %s\n%s" % (" ".join(cmd), result.stderr))
    return result.stdout


def metrics(penumbra, image, reference):
    j = json.loads(run([penumbra, "diff", image, reference, "--json"]))
    return {"mse": j["mse"], "rel_mse": j["rel_mse"], "tm_mse": j["tone_mapped_mse"]}


def mean_std(values):
    m = sum(values) / len(values)
    s = math.sqrt(sum((v - m) ** 2 for v in values) / (len(values) - 1)) if len(values) > 1 else 0
    return m, s


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--penumbra", default="build/penumbra")
    ap.add_argument("--refs", default="out/ref")
    ap.add_argument("--ref-spp", type=int, default=2048)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--scenes", default="stairs,balls,tire,dragon")
    ap.add_argument("--out", default="")
    args = ap.parse_args()
    os.makedirs(args.refs, exist_ok=True)
    work = tempfile.mkdtemp(prefix="bp_results_")
    lines = []

    def emit(text):
        print(text, flush=True)
        lines.append(text)

    emit("| scene | spp | method | kept spp | traced spp | MSE | relMSE | tone-mapped MSE | time (s) |")
    emit("|---|---|---|---|---|---|---|---|---|")
    for scene in args.scenes.split(","):
        spp = PAPER_SPP[scene]
        path = "scenes/%s.json" % scene
        ref = os.path.join(args.refs, scene + ".exr")
        if not os.path.exists(ref):
            print("rendering reference %s at %d spp" % (ref, args.ref_spp), file=sys.stderr)
            run([args.penumbra, "render", path, "--spp", str(args.ref_spp), "--seed", "999",
                 "-o", ref, "-q"])
        rows = {}  # label -> list of (metrics, kept, traced, time)

        def add(label, image, stats):
            m = metrics(args.penumbra, image, ref)
            s = json.load(open(stats))
            kept = s.get("kept_spp", s["spp"])
            traced = s.get("traced_spp", s["spp"])
            rows.setdefault(label, []).append((m, kept, traced, s["time_seconds"]))

        for seed in range(1, args.seeds + 1):
            base = os.path.join(work, "%s_%d" % (scene, seed))
            common = ["--seed", str(seed), "-q"]
            run([args.penumbra, "render", path, "--method", "bp", "--spp", str(spp),
                 "-o", base + "_bp.exr", "--raw-out", base + "_bpraw.exr",
                 "--stats", base + "_bp.json"] + common)
            add("BP", base + "_bp.exr", base + "_bp.json")
            add("BP sampling only (raw)", base + "_bpraw.exr", base + "_bp.json")
            traced = round(json.load(open(base + "_bp.json"))["traced_spp"])
            run([args.penumbra, "render", path, "--method", "bp", "--preset", "tuned",
                 "--spp", str(spp), "-o", base + "_bpt.exr", "--raw-out", base + "_bptraw.exr",
                 "--stats", base + "_bpt.json"] + common)
            add("BP --preset tuned", base + "_bpt.exr", base + "_bpt.json")
            add("BP tuned sampling only (raw)", base + "_bptraw.exr", base + "_bpt.json")
            ld_spps = [("LD", spp), ("LD equal traced", traced)]
            if scene == "tire":
                ld_spps.append(("LD@64", 64))
            for label, n in ld_spps:
                out = "%s_ld%d" % (base, n)
                run([args.penumbra, "render", path, "--spp", str(n), "-o", out + ".exr",
                     "--stats", out + ".json"] + common)
                add(label, out + ".exr", out + ".json")
        for label, runs in rows.items():
            cells = []
            for key in ("mse", "rel_mse", "tm_mse"):
                m, s = mean_std([r[0][key] for r in runs])
                cells.append("%.3e ± %.1e" % (m, s))
            kept = sum(r[1] for r in runs) / len(runs)
            traced = sum(r[2] for r in runs) / len(runs)
            secs = sum(r[3] for r in runs) / len(runs)
            emit("| %s | %d | %s | %.1f | %.1f | %s | %.2f |" %
                 (scene, spp, label, kept, traced, " | ".join(cells), secs))
    if args.out:
        with open(args.out, "w") as f:
            f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
