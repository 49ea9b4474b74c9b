"""The benchmarks page, generated from the JSON files that the benchmark
scripts write (Testing/Benchmarks/results.py: one file per benchmark in
docs/benchmarks/), so that the page shows their latest figures and cannot
disagree with them."""
import glob
import json
import os

REQUIRED = ("capability", "title", "peer", "data", "machine", "date", "command", "columns", "rows")


def load(directory):
    """Every benchmark record, sorted by capability and title; raises on a malformed one."""
    records = []
    for path in sorted(glob.glob(os.path.join(directory, "*.json"))):
        with open(path, encoding="utf-8") as f:
            record = json.load(f)
        missing = [k for k in REQUIRED if k not in record]
        if missing:
            raise ValueError(f"{path}: missing {', '.join(missing)}")
        for row in record["rows"]:
            if len(row) != len(record["columns"]):
                raise ValueError(f"{path}: a row of {len(row)} cells under {len(record['columns'])} columns")
        record["file"] = os.path.basename(path)
        records.append(record)
    return sorted(records, key=lambda r: (r["capability"], r["title"]))


def cell(value):
    if isinstance(value, float):
        text = f"{value:.3g}" if abs(value) < 1e4 else f"{value:,.0f}"
    else:
        text = str(value)
    return text.replace("|", "\\|")


def table(record):
    lines = ["| " + " | ".join(cell(c) for c in record["columns"]) + " |",
             "|" + "---|" * len(record["columns"])]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in record["rows"]]
    return lines


def markdown(records):
    lines = []
    capability = None
    for r in records:
        if r["capability"] != capability:
            capability = r["capability"]
            lines += [f"## {capability}", ""]
        lines += [f"### {r['title']}", "",
                  f"Peer: {r['peer']}. Data: {r['data']}. Machine: {r['machine']}. Date: {r['date']}.", "",
                  f"Command: `{r['command']}`", ""]
        lines += table(r) + [""]
        if r.get("notes"):
            lines += [r["notes"], ""]
    return "\n".join(lines)


def write_markdown(directory, path):
    from reference import write_if_changed
    write_if_changed(path, markdown(load(directory)))
