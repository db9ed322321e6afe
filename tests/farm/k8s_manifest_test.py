#!/usr/bin/env python3
"""Checks scripts/farm/indexed_job.yaml without a cluster (Debian's kubectl predates Indexed
Jobs): the fields an Indexed Job needs, then runs each pod's command here, with
JOB_COMPLETION_INDEX set as Kubernetes sets it, on a real plan (a sharded reference of cornell),
then the finishing Job's command, and compares the merged reference with the unsharded one
byte for byte. Needs python3-yaml (scripts/setup.sh --farm).
Usage: k8s_manifest_test.py PENUMBRA SOURCE_DIR"""
import filecmp
import os
import subprocess
import sys
import tempfile

import yaml

penumbra, src = (os.path.realpath(a) for a in sys.argv[1:3])
failures = []


def check(what, ok):
    print(("ok: " if ok else "FAIL: ") + what)
    if not ok:
        failures.append(what)


with open(os.path.join(src, "scripts/farm/indexed_job.yaml")) as f:
    docs = [d for d in yaml.safe_load_all(f) if d]
tasks, finish = docs
check("two Jobs", [d["kind"] for d in docs] == ["Job", "Job"] and
      all(d["apiVersion"] == "batch/v1" for d in docs))
spec = tasks["spec"]
check("the tasks Job is Indexed", spec.get("completionMode") == "Indexed")
check("completions and parallelism are whole numbers",
      isinstance(spec.get("completions"), int) and isinstance(spec.get("parallelism"), int))
check("pods are not restarted in place (Never)",
      spec["template"]["spec"]["restartPolicy"] == "Never" and
      finish["spec"]["template"]["spec"]["restartPolicy"] == "Never")
containers = [d["spec"]["template"]["spec"]["containers"][0] for d in docs]
plans = [{e["name"]: e["value"] for e in c["env"]}.get("PENUMBRA_PLAN") for c in containers]
check("both name the plan in PENUMBRA_PLAN", all(plans))
check("the labels select each step", [d["metadata"]["labels"]["penumbra-step"] for d in docs] ==
      ["tasks", "finish"])

with tempfile.TemporaryDirectory() as work:
    plan = os.path.join(work, "plan")
    scene = [os.path.join(src, "scenes/cornell.json"), "--size", "64x64", "--spp", "64"]
    subprocess.run([penumbra, "reference", *scene, "--plan", plan, "--shards",
                    str(spec["completions"]), "-o", os.path.join(work, "k8s/ref.exr"), "-q"],
                   check=True)
    lines = open(os.path.join(plan, "tasks.txt")).read().splitlines()
    check("the plan has as many tasks as the Job's completions", len(lines) == spec["completions"])
    env = dict(os.environ, PENUMBRA_PLAN=plan)
    for index in range(spec["completions"]):
        run = subprocess.run(containers[0]["command"], env=dict(env, JOB_COMPLETION_INDEX=str(index)))
        part = os.path.join(plan, "parts", f"part_{index}.shard.json")
        check(f"pod {index} ran task {index} (its part's record exists)",
              run.returncode == 0 and os.path.exists(part))
    past = subprocess.run(containers[0]["command"],
                          env=dict(env, JOB_COMPLETION_INDEX=str(spec["completions"])))
    check("an index past the plan fails", past.returncode != 0)
    run = subprocess.run(containers[1]["command"], env=env, stdout=subprocess.DEVNULL)
    check("the finishing Job merged", run.returncode == 0)
    subprocess.run([penumbra, "reference", *scene, "-o", os.path.join(work, "one/ref.exr"), "-q"],
                   check=True)
    check("the merged reference equals the unsharded one byte for byte",
          filecmp.cmp(os.path.join(work, "one/ref.exr"), os.path.join(work, "k8s/ref.exr"),
                      shallow=False))

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("all Kubernetes manifest checks passed")
