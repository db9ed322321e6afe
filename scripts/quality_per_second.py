"""Quality per second (issue 12): the experiments behind docs/RESULTS.md's "Quality per
second" section, run by scripts/reproduce.py (also alone: reproduce.py --only quality).

  equal time   2 s and 8 s per run on the five shipped scenes: LD, LD with the consistent
               reconstruction (ld:filtered), GEM, BP's default (consistent) preset and the same
               with its networks steering (bp:network-weight=1); MSE, relMSE, speckles,
               curves
  equal spp    16 spp, and BP@16 against LD@64 on the tyre
  convergence  balls and cornell at 16..1024 spp, 3 seeds: LD and BP against 32768-spp
               references (--conv-refs), log-log slopes from 256 to 1024 spp
  overhead     train + select + reconstruct over wall time, BP's default at 16 and 64 spp
"""
import math
import os

import matplotlib.pyplot as plt

SCENES = ["balls", "cornell", "dragon", "stairs", "tire"]
EQUAL_TIME_METHODS = "ld,ld:filtered,gem,bp,bp:network-weight=1"
EQUAL_SPP_METHODS = "ld,ld:filtered,gem,bp,bp:tuned,bp:slice-steering=1"
BEGIN = "<!-- BEGIN GENERATED quality by scripts/reproduce.py: edits below are overwritten -->"
END = "<!-- END GENERATED quality -->"
STYLES = {"ld": ("LD", "#4c72b0"), "ld:filtered": ("LD filtered", "#8172b2"),
          "gem": ("GEM", "#55a868"), "bp": ("BP (default)", "#c44e52"),
          "bp:network-weight=1": ("BP with networks", "#dd8452")}


def by_label(results):
    if not isinstance(results, dict):  # a result a later stage of a --plan makes
        return results
    return {m["label"]: m for m in results["methods"]}


def mean(stat):
    return stat["mean"] if stat and stat.get("mean") is not None else float("nan")


def mean_curve(method):
    """The mean over seeds of (seconds, mse, rel_mse) at the checkpoints every seed has."""
    runs = [run.get("curve") or [] for run in method["runs"]]
    if not runs or not all(runs):
        return []
    common = set(p["checkpoint"] for p in runs[0])
    for c in runs[1:]:
        common &= set(p["checkpoint"] for p in c)
    points = []
    for checkpoint in sorted(common, key=lambda k: (k < 0, k)):
        rows = [next(p for p in c if p["checkpoint"] == checkpoint) for c in runs]
        points.append(tuple(sum(r[k] for r in rows) / len(rows)
                            for k in ("seconds", "mse", "rel_mse")))
    return sorted(points)


def slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(max(y, 1e-30)) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)


def run(r, args, figures, ref_records):
    seeds_time = 1 if args.quick else 2
    times = [0.5] if args.quick else [2.0, 8.0]
    conv_spp = [16, 32] if args.quick else [16, 32, 64, 128, 256, 512, 1024]
    equal_time = {}
    for seconds in times:
        for scene in SCENES:
            equal_time[(scene, seconds)] = by_label(r.compare(
                "quality_%s_%gs" % (scene, seconds), scene, 16, EQUAL_TIME_METHODS,
                ["--equal-time", "%g" % seconds], seeds=seeds_time))
    equal_spp = {}
    for scene in SCENES:
        methods = EQUAL_SPP_METHODS + (",ld@64" if scene == "tire" else "")
        equal_spp[scene] = by_label(r.compare("quality_%s_16spp" % scene, scene, 16, methods,
                                              ["--no-curve"]))
    # The convergence runs are measured against references of many more samples than the
    # others' (32768 spp): a reference of R spp measures a method's error reliably only up to
    # about R/16 spp, past which its own error is a large part of what is measured and the
    # slope flattens.
    conv_records = {scene: r.ensure_reference(scene, args.conv_refs, args.conv_ref_spp)
                    for scene in ("balls", "cornell")}
    conv_seeds = 1 if args.quick else 3
    convergence = {}
    for scene in ("balls", "cornell"):
        for spp in conv_spp:
            convergence[(scene, spp)] = by_label(r.compare(
                "quality_conv_%s_%d" % (scene, spp), scene, spp, "ld,bp", ["--no-curve"],
                seeds=conv_seeds, refs=args.conv_refs))

    at64 = {scene: by_label(r.compare("quality_%s_64spp" % scene, scene, 64, "bp",
                                      ["--no-curve"])) for scene in ("balls", "tire")}
    # Numbers only once every run has been asked for, so that a --plan stage plans them all.
    overhead = {}
    for scene in ("balls", "tire"):
        for spp in (16, 64):
            m = (equal_spp[scene] if spp == 16 else at64[scene])["bp"]
            overhead[(scene, spp)] = (mean(m["train"]) + mean(m["select"]) +
                                      mean(m["reconstruct"])) / mean(m["seconds"])

    # ---- The time-to-quality plot: MSE and relMSE against wall seconds, 8 s runs ----------
    longest = times[-1]
    fig, axes = plt.subplots(2, len(SCENES), figsize=(3.2 * len(SCENES), 6.0),
                             layout="constrained")
    for i, scene in enumerate(SCENES):
        for row, (key, name) in enumerate((("mse", "MSE"), ("rel_mse", "relMSE"))):
            ax = axes[row][i]
            for label, (text, color) in STYLES.items():
                points = mean_curve(equal_time[(scene, longest)][label])
                if points:
                    ax.plot([p[0] for p in points], [p[1 if key == "mse" else 2] for p in points],
                            color=color, marker="o", markersize=3, label=text)
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.grid(True, which="both", alpha=0.3)
            ax.set_xlabel("wall seconds")
            if i == 0:
                ax.set_ylabel(name)
            if row == 0:
                ax.set_title(scene)
    axes[0][0].legend(fontsize=7)
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(figures, "time_to_quality.%s" % ext), dpi=100,
                    bbox_inches="tight")
    plt.close(fig)

    # ---- Markdown -------------------------------------------------------------------
    out = [BEGIN, "", "## Quality per second (issue 12)", ""]
    emit = out.append
    emit("Generated by `scripts/reproduce.py%s`. `bp` is BP's default preset (consistent: the "
         "film's consistent reconstruction, samples where the raw estimate's relative variance "
         "per ray is highest); `ld:filtered` the same "
         "reconstruction on plain LD samples; `bp:network-weight=1` the same with its networks' bias steering the samples (the preset "
         "leaves it at 0: see the goals). "
         "Errors against %d-spp references; ratios are to LD's mean over %d seeds (equal time) "
         "or %d (equal spp)." % (" --quick" if args.quick else "", args.ref_spp, seeds_time,
                                  args.seeds))
    emit("")
    emit("![time to quality](%s/time_to_quality.png)" %
         os.path.relpath(figures, os.path.dirname(args.docs) or "."))
    emit("")
    emit("*MSE (top) and relMSE (bottom) against each method's own wall seconds, %g s runs, "
         "mean over seeds, log-log.*" % longest)
    emit("")
    goals = {"time": [], "gem": [], "net": [], "speckle": []}
    for seconds in times:
        emit("### Equal time, %g s per run: MSE × LD (relMSE × LD), speckles" % seconds)
        emit("")
        emit("| scene | LD MSE | " + " | ".join(STYLES[k][0] for k in list(STYLES)[1:]) + " |")
        emit("|---|--:|" + "--:|" * (len(STYLES) - 1))
        for scene in SCENES:
            row = equal_time[(scene, seconds)]
            ld = row["ld"]
            cells = []
            for label in list(STYLES)[1:]:
                m = row[label]
                cells.append("%.2f (%.2f), %.2f%%" % (
                    mean(m["mse"]) / mean(ld["mse"]), mean(m["rel_mse"]) / mean(ld["rel_mse"]),
                    100 * mean(m.get("speckles"))))
            emit("| %s | %.2e | %s |" % (scene, mean(ld["mse"]), " | ".join(cells)))
            bp = row["bp"]
            goals["time"].append(max(mean(bp["mse"]) / mean(ld["mse"]),
                                     mean(bp["rel_mse"]) / mean(ld["rel_mse"])))
            goals["gem"].append(mean(bp["mse"]) < mean(row["gem"]["mse"]))
            goals["net"].append(mean(bp["mse"]) / mean(row["ld:filtered"]["mse"]))
            if seconds == 2.0 or args.quick:
                goals["speckle"].append(mean(bp.get("speckles")))
        emit("")
    emit("### Equal 16 spp: MSE × LD (relMSE × LD)")
    emit("")
    emit("| scene | LD MSE | " + " | ".join(EQUAL_SPP_METHODS.split(",")[1:]) + " | LD@64 |")
    emit("|---|--:|" + "--:|" * len(EQUAL_SPP_METHODS.split(",")) )
    spp_ratios = []
    for scene in SCENES:
        row = equal_spp[scene]
        ld = row["ld"]
        cells = ["%.2f (%.2f)" % (mean(row[l]["mse"]) / mean(ld["mse"]),
                                  mean(row[l]["rel_mse"]) / mean(ld["rel_mse"]))
                 for l in EQUAL_SPP_METHODS.split(",")[1:]]
        cells.append("%.2f" % (mean(row["ld@64"]["mse"]) / mean(ld["mse"]))
                     if "ld@64" in row else "")
        spp_ratios.append(mean(row["bp"]["mse"]) / mean(ld["mse"]))
        emit("| %s | %.2e | %s |" % (scene, mean(ld["mse"]), " | ".join(cells)))
    emit("")
    tire = equal_spp["tire"]
    claim = mean(tire["bp"]["mse"]) <= mean(tire["ld@64"]["mse"])
    emit("BP@16 against LD@64 on the tyre (the paper's claim): MSE %.2e against %.2e: %s." % (
        mean(tire["bp"]["mse"]), mean(tire["ld@64"]["mse"]), "holds" if claim else "does not hold"))
    emit("")
    # The slope is fitted from 256 to 1024 spp (the range), where a consistent filter's
    # error must already fall nearly as fast as the raw estimate's; BP must be below LD at every
    # spp the references measure reliably (up to their spp / 16).
    conv_ref_spp = min(rec["spp"] for rec in conv_records.values())
    reliable = [s for s in conv_spp if s <= conv_ref_spp / 16] or conv_spp[:2]
    fit = [s for s in reliable if s >= 256] or reliable[-2:]
    emit("### Convergence (%d seed%s)" % (conv_seeds, "" if conv_seeds == 1 else "s"))
    emit("")
    emit("MSE against %d-spp references (`--conv-refs`), mean over seeds; their own residual "
         "MSE (an iid estimate, which over-states a low-discrepancy reference's) is %s. The "
         "slope is fitted over %s spp, as measured and less an estimate of the reference's own "
         "error: LD's measured MSE at %d spp scaled by %d/R (LD's error falls at least as 1/n, "
         "so this is an upper bound and the second slope a little steep)." % (
             conv_ref_spp, ", ".join(
                 "%.1e on %s" % (conv_records[sc].get("residual_mse", float("nan")), sc)
                 for sc in ("balls", "cornell")), "–".join(str(s) for s in (fit[0], fit[-1])),
             conv_spp[-1], conv_spp[-1]))
    emit("")
    emit("| scene | method | " + " | ".join(str(s) for s in conv_spp) +
         " | slope %d-%d | less the reference's error |" % (fit[0], fit[-1]))
    emit("|---|---|" + "--:|" * (len(conv_spp) + 2))
    slopes = {}
    below = 0
    for scene in ("balls", "cornell"):
        ref_error = mean(convergence[(scene, conv_spp[-1])]["ld"]["mse"]) * conv_spp[-1] / \
            conv_ref_spp
        for label in ("ld", "bp"):
            ys = [mean(convergence[(scene, s)][label]["mse"]) for s in conv_spp]
            fitted = [mean(convergence[(scene, s)][label]["mse"]) for s in fit]
            k = slope(fit, fitted) if len(fit) >= 2 else float("nan")
            less = slope(fit, [y - ref_error for y in fitted]) \
                if len(fit) >= 2 and min(fitted) > ref_error else float("nan")
            slopes[(scene, label)] = k
            slopes[(scene, label, "less")] = less
            emit("| %s | %s | %s | %.2f | %.2f |" % (
                scene, label, " | ".join("%.2e" % y for y in ys), k, less))
        below += all(mean(convergence[(scene, s)]["bp"]["mse"]) <=
                     mean(convergence[(scene, s)]["ld"]["mse"]) for s in reliable)
    emit("")
    emit("### Overhead of BP's default: (train + select + reconstruct) / wall time")
    emit("")
    emit("| scene | 16 spp | 64 spp |")
    emit("|---|--:|--:|")
    for scene in ("balls", "tire"):
        emit("| %s | %.0f%% | %.0f%% |" % (scene, 100 * overhead[(scene, 16)],
                                          100 * overhead[(scene, 64)]))
    emit("")
    emit("### Goals")
    emit("")

    def verdict(ok):
        return "met" if ok else "**missed**"
    emit("- Equal time, BP ≤ 0.25× LD in MSE and relMSE on every scene: worst %.2f× — %s." % (
        max(goals["time"]), verdict(max(goals["time"]) <= 0.25)))
    emit("- BP below GEM on each scene at equal time: %d of %d runs — %s." % (
        sum(goals["gem"]), len(goals["gem"]), verdict(all(goals["gem"]))))
    net_ok = sum(v <= 0.8 for v in goals["net"])
    emit("- What the networks and the sampling add: BP ≤ 0.8× `ld:filtered` in %d of %d "
         "(scene, time) pairs (goal: four of five scenes) — %s. BP with its networks "
         "against BP: see the last column of the tables." % (
             net_ok, len(goals["net"]), verdict(net_ok >= 0.8 * len(goals["net"]))))
    emit("- Equal 16 spp, BP ≤ 0.25× LD on every scene: worst %.2f× — %s; BP@16 ≤ LD@64 on "
         "the tyre — %s." % (max(spp_ratios), verdict(max(spp_ratios) <= 0.25), verdict(claim)))
    worst_slope = max(slopes[(s, "bp")] for s in ("balls", "cornell"))
    worst_less = max(slopes[(s, "bp", "less")] for s in ("balls", "cornell"))
    emit("- Convergence: BP ≤ LD at every spp up to %d on %d of 2 scenes — %s; BP's slope from "
         "%d to %d spp %.2f at worst as measured (%.2f less the reference's error; goal ≤ −0.7) "
         "— %s." % (reliable[-1], below, verdict(below == 2), fit[0], fit[-1], worst_slope,
                    worst_less, verdict(worst_slope <= -0.7)))
    emit("- Speckles at equal 2 s: BP's share of pixels above LD's 99.9th percentile of "
         "relative squared error, worst %.2f%% (goal ≤ 0.1%%) — %s." % (
             100 * max(goals["speckle"]), verdict(max(goals["speckle"]) <= 0.001)))
    emit("- Overhead ≤ 20%% at 16 and 64 spp on balls and tire: worst %.0f%% — %s." % (
        100 * max(overhead.values()), verdict(max(overhead.values()) <= 0.2)))
    emit("")
    emit(END)
    return out


def write(docs, lines):
    text = open(docs).read() if os.path.exists(docs) else "# Results\n"
    block = "\n".join(lines)
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        text = head + block + rest.split(END, 1)[1]
    else:
        # Before the paper's section: quality per second is the headline.
        marker = "<!-- BEGIN GENERATED by scripts/reproduce.py"
        if marker in text:
            head, rest = text.split(marker, 1)
            text = head + block + "\n\n" + marker + rest
        else:
            text = text.rstrip() + "\n\n" + block + "\n"
    tmp = docs + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, docs)
