"""Long coverage-guided fuzzing runs of every reader (tests/fuzz/fuzz_readers.py), two formats at a time.

    python benchmarks/bench_fuzz.py --seconds 600 --out benchmarks/fuzz_results.md [FORMAT ...]

For each format: the seeds written by the harness, then libFuzzer for ``--seconds``; a row with the
executions, the coverage (libFuzzer's ``cov`` edges and ``ft`` features at the end), the corpus grown and
the findings (crash, timeout and out-of-memory files left in the format's folder under ``--work``). Each
row is appended to ``--out`` as soon as its run ends, so a stopped benchmark keeps the rows it finished.
"""
from __future__ import annotations

import argparse
import re
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HARNESS = ROOT / "tests" / "fuzz" / "fuzz_readers.py"
sys.path.insert(0, str(HARNESS.parent))
from fuzz_readers import FORMATS  # noqa: E402


def run(fmt: str, seconds: int, work: Path) -> dict:
    folder = work / fmt
    corpus = folder / "corpus"
    folder.mkdir(parents=True, exist_ok=True)
    subprocess.run([sys.executable, str(HARNESS), fmt, "--seeds", str(corpus)], check=True, capture_output=True)
    seeds = len(list(corpus.iterdir()))
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, str(HARNESS), fmt, f"-max_total_time={seconds}", "-rss_limit_mb=3072",
                           "-timeout=30", "-print_final_stats=1", str(corpus)], cwd=folder, capture_output=True,
                          text=True, errors="replace")
    wall = time.perf_counter() - t0
    log = done.stdout + done.stderr
    (folder / "log.txt").write_text(log[-200_000:])
    cov = re.findall(r"cov: (\d+) ft: (\d+)", log)
    runs = re.findall(r"stat::number_of_executed_units: (\d+)", log)
    findings = sorted(p.name for p in folder.iterdir() if re.match(r"(crash|timeout|oom|leak|slow-unit)-", p.name))
    return {"format": fmt, "seconds": round(wall), "executions": int(runs[-1]) if runs else None,
            "cov": int(cov[-1][0]) if cov else None, "ft": int(cov[-1][1]) if cov else None, "seeds": seeds,
            "corpus": len(list(corpus.iterdir())), "exit": done.returncode, "findings": findings}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("formats", nargs="*", default=list(FORMATS))
    ap.add_argument("--seconds", type=int, default=600)
    ap.add_argument("--parallel", type=int, default=2)
    ap.add_argument("--work", type=Path, default=Path("/tmp/geoimg-fuzz"))
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args()
    bad = [f for f in args.formats if f not in FORMATS]
    if bad or args.seconds < 1 or args.parallel < 1:
        ap.error(f"formats from {', '.join(FORMATS)}; --seconds and --parallel at least 1")

    def one(fmt: str) -> dict:
        row = run(fmt, args.seconds, args.work)
        line = (f"| {row['format']} | {row['seconds']} | {row['executions']} | {row['cov']} | {row['ft']} | "
                f"{row['seeds']} -> {row['corpus']} | {row['exit']} | {', '.join(row['findings']) or 'none'} |")
        print(line, flush=True)
        if args.out:
            with open(args.out, "a") as fh:
                fh.write(line + "\n")
        return row

    print("| format | s | executions | cov | ft | corpus | exit | findings |\n|---|---|---|---|---|---|---|---|")
    with ThreadPoolExecutor(args.parallel) as pool:
        list(pool.map(one, args.formats))


if __name__ == "__main__":
    main()
