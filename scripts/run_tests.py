#!/usr/bin/env python3
"""Runs the workspace's test binaries two at a time (scripts/test.sh calls this).

    python3 scripts/run_tests.py BUILD_JSON

BUILD_JSON is the output of `cargo test --workspace --all-targets --no-run
--message-format=json`: every test executable it names (unit, integration, and the
benches in test mode) runs with its package's folder as the working directory, as
`cargo test` runs it. Two run at once, the longest first (from the list below; the
rest in name order), because several binaries end with one long single-threaded test
(the board build, the cocotb bench, a Verilator run) that would otherwise leave a
core idle. Each binary's output is printed whole when it ends, under its name. Exits
1 if any binary fails (its output says which test), 2 if the JSON names none.
"""

import json
import os
import subprocess
import sys
import threading
import time

# The longest binaries first, unknown ones after these. cli_and_readme ends with the
# board build (yosys and nextpnr), so it starts at once; the rest in the order of their
# times in a clean-clone run (2026-12-02, 2-core machine: cli_and_readme 634 s,
# hdl_core 397, system 356, model_props 176, export 254, the small sweep 147,
# c_driver 130, hdl_encoder 110).
LONGEST = [
    "cli_and_readme",
    "hdl_core",
    "system",
    "model_props",
    "export",
    "sweep",
    "c_driver",
    "hdl_encoder",
    "vectors_and_report",
    "hdl_step_gen",
]
LANES = 2


def executables(build_json):
    found = []
    with open(build_json) as f:
        for line in f:
            line = line.strip()
            if not line.startswith("{"):
                continue
            msg = json.loads(line)
            if msg.get("reason") != "compiler-artifact" or not msg.get("executable"):
                continue
            t = msg["target"]
            kind = t["kind"][0]
            # Integration tests and benches (criterion's run once each in test mode), and
            # the unit tests of the binary (the library has none); not the binary itself.
            if kind not in ("test", "bench") and not msg.get("profile", {}).get("test"):
                continue
            name = t["name"] if kind in ("test", "bench") else f"{t['name']} ({kind})"
            found.append((name, msg["executable"], os.path.dirname(msg["manifest_path"])))
    return found


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    jobs = executables(sys.argv[1])
    if not jobs:
        print("run_tests: no test executable in the build output", file=sys.stderr)
        return 2
    rank = {n: i for i, n in enumerate(LONGEST)}
    jobs.sort(key=lambda j: (rank.get(j[0], len(LONGEST)), j[0]))
    lock = threading.Lock()
    queue = list(jobs)
    failed = []

    def lane():
        while True:
            with lock:
                if not queue:
                    return
                name, exe, cwd = queue.pop(0)
            t0 = time.time()
            r = subprocess.run([exe], cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
            out = r.stdout.decode(errors="replace")
            with lock:
                print(f"     Running {name} ({os.path.relpath(exe)}): {time.time() - t0:.0f} s, exit {r.returncode}")
                print(out, flush=True)
                if r.returncode != 0:
                    failed.append(name)

    threads = [threading.Thread(target=lane) for _ in range(LANES)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if failed:
        print(f"run_tests: failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
