#!/usr/bin/env python3
"""The summary of scripts/gpu_checks.sh: summary.json and summary.md from what its steps left in
its work folder (steps.tsv, machine.tsv, MANIFEST, harness.json, bench_raster.out) and the training
files in OUT/train. Standard library only: it runs under whichever python3 the machine has."""

import argparse
import json
import os


def read_rows(path):
    if not os.path.exists(path):
        return []
    with open(path, encoding="utf-8") as f:
        return [line.rstrip("\n").split("\t") for line in f if line.strip()]


def read_text(path):
    if not os.path.exists(path):
        return ""
    with open(path, encoding="utf-8", errors="replace") as f:
        return f.read()


def step_failed(status):
    return status.startswith("failed") or status.startswith("timed out")


def collect(work, out, budget, mode):
    steps = [{"name": r[0], "status": r[1], "seconds": float(r[2]), "detail": r[3] if len(r) > 3 else ""}
             for r in read_rows(os.path.join(work, "steps.tsv"))]
    harness_path = os.path.join(work, "harness.json")
    harness = json.loads(read_text(harness_path)) if os.path.exists(harness_path) else None
    harness_step = next((s for s in steps if s["name"] == "harness"), None)
    train_dir = os.path.join(out, "train")
    train_files = sorted(os.listdir(train_dir)) if os.path.isdir(train_dir) else []
    passed = (harness_step is not None and harness_step["status"] == "passed" and harness is not None
              and harness.get("passed") is True and not any(step_failed(s["status"]) for s in steps))
    return {
        "script": "scripts/gpu_checks.sh",
        "mode": mode,
        "budget_s": budget,
        "seconds": round(sum(s["seconds"] for s in steps), 1),
        "payload": read_text(os.path.join(work, "MANIFEST")).splitlines()[:2],
        "machine": {r[0]: r[1] for r in read_rows(os.path.join(work, "machine.tsv"))},
        "steps": steps,
        "harness": harness,
        "bench_raster": read_text(os.path.join(work, "bench_raster.out")).splitlines(),
        "train_files": train_files,
        "passed": passed,
    }


def case_row(case):
    cpu, gpu = case["cpu"], case["gpu"]
    cpu_text = cpu["status"] + (": " + cpu["failure"] if "failure" in cpu else "")
    gpu_text = gpu.get("reason") or gpu["status"] + (": " + gpu["failure"] if "failure" in gpu else "")
    control = cpu.get("control_changed_share")
    close = f"{100 * gpu['close_share']:.2f}%" if "close_share" in gpu else ""
    psnr = f"{gpu['psnr_db']:.1f}" if "psnr_db" in gpu else ""
    drawn = f"{cpu.get('drawn_pixels', '')} / {gpu.get('drawn_pixels', '')}" if "drawn_pixels" in gpu else ""
    return (f"| {case['name']} | {case['checks']} | {cpu_text} | "
            f"{'' if control is None else f'{100 * control:.1f}%'} | {gpu_text} | {close} | {psnr} | {drawn} |")


def markdown(s):
    lines = [f"# GPU checks ({s['mode']})", ""]
    lines += [f"passed: {'yes' if s['passed'] else 'no'}", ""]
    lines += [f"- {k}: {v}" for k, v in s["machine"].items()]
    lines += [f"- payload: {p}" for p in s["payload"]]
    lines += [f"- {s['seconds']} s of the {s['budget_s']} s budget", ""]
    lines += ["| step | status | seconds | detail |", "|---|---|---|---|"]
    lines += [f"| {t['name']} | {t['status']} | {t['seconds']} | {t['detail']} |" for t in s["steps"]]
    h = s["harness"]
    if h:
        p = h["plugin"]
        t = h["tolerance"]
        lines += ["", "## CPU against CUDA (bench/gpu_harness)", "",
                  f"plugin: {p['path'] or 'not found'}; " +
                  (f"device {p['device']}" if not p["unavailable"] else f"unavailable: {p['unavailable']}") +
                  f"; report {'clean' if p['clean'] else 'NOT clean'}. GPU side: {h['gpu_side']}.",
                  f"A GPU frame passes with at least {100 * t['min_close_share']:.0f}% of its pixels within "
                  f"{t['max_level_difference']} levels of the CPU's and the drawn pixels within "
                  f"{100 * t['max_drawn_difference_share']:.1f}% of the image; a case's CPU frame differs from its "
                  f"control's in at least {100 * t['min_control_changed_share']:.0f}% of the pixels.", "",
                  "| case | checks | CPU | control changes | GPU | within levels | PSNR dB | drawn CPU / GPU |",
                  "|---|---|---|---|---|---|---|---|"]
        lines += [case_row(c) for c in h["cases"]]
    if s["bench_raster"]:
        lines += ["", "## bench_raster", "", "```"] + s["bench_raster"] + ["```"]
    if s["train_files"]:
        lines += ["", "## training (train/)", ""] + [f"- {f}" for f in s["train_files"]]
    return "\n".join(lines) + "\n"


def write(path, text):
    with open(path + ".part", "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(path + ".part", path)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--work", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--budget", type=int, required=True)
    parser.add_argument("--mode", required=True)
    a = parser.parse_args()
    summary = collect(a.work, a.out, a.budget, a.mode)
    write(os.path.join(a.out, "summary.json"), json.dumps(summary, indent=1) + "\n")
    write(os.path.join(a.out, "summary.md"), markdown(summary))


if __name__ == "__main__":
    main()
