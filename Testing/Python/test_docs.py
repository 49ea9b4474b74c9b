"""The user guide (docs/) and the README, as a user meets them:
  - the HTML builds with Sphinx with warnings as errors (-W);
  - every proxy of the plugin has its settings table on a page of the guide,
    and every setting (label and Python setter) appears there; every other
    public Set/Add method of the filters appears somewhere in the guide;
  - no internal link of the HTML is broken (files and anchors);
  - every example in docs/examples/ is shown by a page (the suite runs them:
    Docs.Examples and Docs.ExamplesPvpython);
  - the setters' comments in the headers are the XML's (docs/reference.py);
  - the README has at most 250 lines, and no text of the repository speaks
    of sessions, virtual machines or issue numbers (that history is the git
    log's).
Exits 77 (skipped) with a message where the Sphinx packages are absent."""
import glob
import html
import importlib.util
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
DOCS = os.path.join(ROOT, "docs")
sys.path.insert(0, DOCS)
import reference  # noqa: E402

problems = []
# Words of a development history, not of a user's documentation.
HISTORY = re.compile(r"\bissues? #?\d+|\bsessions? \d+|\b(this|last|previous|next|that) session\b|"
                     r"virtual machines?|\bVMs?\b|\b(EPYC|Xeon|Ryzen|Opteron)\b", re.IGNORECASE)
TEXT_SUFFIXES = (".md", ".py", ".h", ".cxx", ".xml", ".txt", ".sh", ".in", ".module", ".plugin", ".json", "run")


def fail(text):
    problems.append(text)
    print("FAILED:", text)


def page_text(path):
    text = open(path, encoding="utf-8").read()
    text = re.sub(r"<script.*?</script>|<style.*?</style>", " ", text, flags=re.S)
    return html.unescape(re.sub(r"<[^>]+>", " ", text))


def build(out):
    run = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", DOCS, out],
                         capture_output=True, text=True)
    if run.returncode != 0:
        fail("the guide does not build without warnings:\n" + run.stdout + run.stderr)
        return False
    return True


def sources_including(name):
    """The guide's pages (docs/**/*.md) that include the settings table of proxy `name`."""
    pages = []
    for path in glob.glob(os.path.join(DOCS, "**", "*.md"), recursive=True):
        if "_generated" not in path and f"_generated/settings/{name}.md" in open(path, encoding="utf-8").read():
            pages.append(os.path.relpath(path, DOCS)[:-3] + ".html")
    return pages


def check_reference(out):
    proxies = reference.proxies()
    if len(proxies) < 15:
        fail(f"only {len(proxies)} proxies read from the plugin XML")
    for p in proxies:
        pages = sources_including(p.name)
        if not pages:
            fail(f"no page of the guide shows the settings of {p.label} ({p.name})")
            continue
        text = " ".join(page_text(os.path.join(out, page)) for page in pages)
        for s in p.settings:
            if s.information_only:
                continue
            if not s.doc:
                fail(f"{p.label}: the setting {s.label} has no <Documentation> in {p.file}")
            for word in (s.label, s.setter):
                if word and word not in text:
                    fail(f"{p.label}: the setting '{word}' is not in {', '.join(pages)}")
    return proxies


def check_python_only(proxies, everything):
    """Every public Set/Add method of the filters, beyond the XML's, is named in the guide."""
    try:
        import beltrami
    except ImportError:
        fail("the beltrami package does not import: source build/beltrami-env.sh")
        return
    for p in proxies:
        cls = getattr(beltrami, p.cls, None)
        if cls is None:
            continue
        base = dir(cls.__mro__[1])
        commands = {s.command for s in p.settings}
        for method in dir(cls):
            if (method.startswith("Set") or method.startswith("Add")) and method not in base \
                    and method not in commands and not method.endswith("On") and method not in everything:
                fail(f"{p.cls}.{method} is public but the guide does not name it")


def check_links(out):
    ids = {}
    for path in glob.glob(os.path.join(out, "**", "*.html"), recursive=True):
        text = open(path, encoding="utf-8").read()
        ids[os.path.normpath(path)] = set(re.findall(r'id="([^"]+)"', text))
    broken = 0
    for path in ids:
        for href in re.findall(r'href="([^"]+)"', open(path, encoding="utf-8").read()):
            if re.match(r"[a-z]+:", href) or href.startswith("//"):
                continue
            target, _, anchor = href.partition("#")
            target = target.split("?")[0]
            target = os.path.normpath(os.path.join(os.path.dirname(path), target)) if target else path
            if not os.path.exists(target):
                broken += 1
                fail(f"{os.path.relpath(path, out)}: broken link {href}")
            elif anchor and target.endswith(".html") and anchor not in ids.get(target, set()):
                broken += 1
                fail(f"{os.path.relpath(path, out)}: no anchor {href}")
    print(f"links checked in {len(ids)} pages")


def check_examples():
    shown = " ".join(open(p, encoding="utf-8").read()
                     for p in glob.glob(os.path.join(DOCS, "**", "*.md"), recursive=True))
    for example in sorted(glob.glob(os.path.join(DOCS, "examples", "*.py"))):
        if "examples/" + os.path.basename(example) not in shown:
            fail(f"docs/examples/{os.path.basename(example)} is shown by no page")


def check_headers():
    changes = reference.header_changes()
    for path in changes:
        fail(f"{os.path.relpath(path, ROOT)}: the setters' comments differ from the XML "
             "(python3 docs/reference.py --write-headers)")


def tracked_text_files():
    run = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True)
    if run.returncode != 0:  # not a clone: the folders a user reads
        names = [os.path.relpath(p, ROOT) for d in ("docs", "Examples", "ParaViewPlugin", "Filters", "IO", "Python",
                                                   "Testing") for p in glob.glob(os.path.join(ROOT, d, "**", "*"),
                                                                                 recursive=True)]
        names += ["README.md", "beltrami.sh", "CMakeLists.txt"]
    else:
        names = run.stdout.split()
    return [n for n in names if n.endswith(TEXT_SUFFIXES) and os.path.isfile(os.path.join(ROOT, n))]


def check_history():
    readme = open(os.path.join(ROOT, "README.md"), encoding="utf-8").read().split("\n")
    if len(readme) > 250:
        fail(f"README.md has {len(readme)} lines (at most 250)")
    for target in re.findall(r"\]\(([^)#]+)", "\n".join(readme)):
        if not re.match(r"[a-z]+:", target) and not os.path.exists(os.path.join(ROOT, target)):
            fail(f"README.md links to {target}, which is not there")
    files = tracked_text_files()
    for name in files:
        for number, line in enumerate(open(os.path.join(ROOT, name), encoding="utf-8", errors="replace"), 1):
            if name != "Testing/Python/test_docs.py" and HISTORY.search(line):
                fail(f"{name}:{number}: speaks of the development's history: {line.strip()[:100]}")
    print(f"README {len(readme)} lines; {len(files)} files read for history")


def main():
    missing = [m for m in ("sphinx", "myst_parser", "furo") if importlib.util.find_spec(m) is None]
    if missing:
        print("SKIPPED: the user guide needs " + ", ".join(missing) +
              " (apt install python3-sphinx python3-myst-parser furo; ./beltrami.sh installs them)")
        return 77
    check_history()
    check_headers()
    check_examples()
    with tempfile.TemporaryDirectory() as out:
        if build(out):
            proxies = check_reference(out)
            everything = " ".join(page_text(p) for p in glob.glob(os.path.join(out, "**", "*.html"), recursive=True))
            check_python_only(proxies, everything)
            check_links(out)
    if problems:
        print(f"{len(problems)} problem(s)")
        return 1
    print("docs test passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
