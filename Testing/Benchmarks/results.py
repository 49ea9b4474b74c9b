"""What a benchmark script writes for the user guide's benchmarks page:
one JSON file per benchmark in docs/benchmarks/ (BELTRAMI_BENCHMARK_DIR
overrides the folder), with the machine and the date, replaced at every
run so that the page shows the latest figures only (docs/benchmarks.py)."""
import datetime
import json
import os
import platform
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def machine():
    """This machine's kind in words: architecture, widest vector unit, cores, memory
    (no vendor's model name: the page describes the class of machine)."""
    vector = ""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            flags = next((line.split(":", 1)[1].split() for line in f if line.startswith("flags")), [])
        vector = " with AVX-512" if "avx512f" in flags else " with AVX2" if "avx2" in flags else ""
    except OSError:
        pass
    memory = ""
    try:
        with open("/proc/meminfo", encoding="utf-8") as f:
            kib = int(f.readline().split()[1])
        memory = f", {kib / 2**20:.0f} GiB"
    except (OSError, ValueError, IndexError):
        pass
    return f"{platform.machine()}{vector}, {os.cpu_count()} cores{memory}"


def save(name, capability, title, peer, data, columns, rows, notes=""):
    """Writes docs/benchmarks/<name>.json; returns its path."""
    record = {"capability": capability, "title": title, "peer": peer, "data": data,
              "machine": machine(), "date": datetime.date.today().isoformat(),
              "command": "/usr/bin/python3 " + " ".join([os.path.relpath(os.path.abspath(sys.argv[0]), ROOT)]
                                                        + sys.argv[1:]),
              "columns": list(columns), "rows": [list(r) for r in rows], "notes": notes}
    directory = os.environ.get("BELTRAMI_BENCHMARK_DIR", os.path.join(ROOT, "docs", "benchmarks"))
    os.makedirs(directory, exist_ok=True)
    path = os.path.join(directory, name + ".json")
    with open(path, "w", encoding="utf-8") as f:
        json.dump(record, f, indent=1)
        f.write("\n")
    print("wrote", path)
    return path
