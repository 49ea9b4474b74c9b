"""The one source of the settings reference: the ParaView plugin's XML
(ParaViewPlugin/*.xml).  Each property's <Documentation>, default and
enumeration are read here and written out three ways, so that they cannot
disagree:
  - the settings tables of the user guide (Markdown, at every docs build);
  - the `///` comments above the setters in the filters' headers, which the
    Python wrapping turns into the setters' docstrings (`--write-headers`
    rewrites them, `--check-headers` lists the ones that differ);
  - the ParaView tooltips, which are the XML itself.
Where a Python user's default differs from the panel's on purpose, the
property says so in the XML: <Hints><PythonDefault value="..." reason="..."/>.
Plain Python, no VTK: run as `python3 docs/reference.py --check-headers`."""
import argparse
import glob
import os
import re
import sys
import textwrap
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PLUGIN = os.path.join(ROOT, "ParaViewPlugin")
HEADER_DIRS = [os.path.join(ROOT, "Filters"), os.path.join(ROOT, "IO")]
# Commands that are not one plain setting of the filter.
NOT_SETTINGS = {"SetInputConnection", "AddInputConnection", "SetFileName"}
PROPERTY_TAGS = ("IntVectorProperty", "IdTypeVectorProperty", "DoubleVectorProperty", "StringVectorProperty",
                 "ProxyProperty")


def clean(text):
    """XML text as one paragraph."""
    return " ".join((text or "").split())


class Setting:
    def __init__(self, el):
        self.name = el.get("name")
        self.label = el.get("label") or re.sub(r"(?<=[a-z0-9])(?=[A-Z])", " ", self.name)
        self.command = el.get("command") or ""
        self.kind = el.tag
        self.information_only = el.get("information_only") == "1"
        self.advanced = el.get("panel_visibility") == "advanced"
        doc = el.find("Documentation")
        self.doc = clean(doc.text if doc is not None else "")
        self.default = el.get("default_values")
        self.entries = [(e.get("value"), e.get("text")) for e in el.iter("Entry")]
        self.boolean = el.find("BooleanDomain") is not None
        hint = el.find("Hints/PythonDefault")
        self.python_default = None if hint is None else hint.get("value")
        self.python_default_reason = None if hint is None else clean(hint.get("reason"))

    @property
    def setter(self):
        """The C++/Python method, or None for an input or an array choice."""
        if not self.command.startswith("Set") or self.command in NOT_SETTINGS:
            return None
        if self.command == "SetInputArrayToProcess":
            return None
        return self.command

    def value_text(self, value):
        if value is None:
            return ""
        if self.boolean:
            return "on" if value.strip() == "1" else "off"
        for v, text in self.entries:
            if v == value.strip():
                return text
        if self.command == "SetInputArrayToProcess":
            return "none" if value.split()[-1] == "None" else value.split()[-1]
        return value

    def default_text(self):
        return self.value_text(self.default)

    def python_default_text(self):
        return self.value_text(self.python_default if self.python_default is not None else self.default)


class Proxy:
    def __init__(self, el, group, path):
        self.name = el.get("name")
        self.label = el.get("label") or self.name
        self.cls = el.get("class")
        self.group = group
        self.file = os.path.basename(path)
        doc = el.find("Documentation")
        self.short_help = clean(doc.get("short_help") if doc is not None else "")
        self.doc = clean(doc.text if doc is not None else "")
        self.settings = [Setting(p) for p in el if p.tag in PROPERTY_TAGS
                         and p.get("name") != "Input" and p.get("panel_visibility") != "never"]


def proxies():
    """Every user-facing proxy of the plugin, in file order."""
    found = []
    for path in sorted(glob.glob(os.path.join(PLUGIN, "*.xml"))):
        for group in ET.parse(path).getroot().iter("ProxyGroup"):
            if group.get("name") not in ("filters", "sources", "writers"):
                continue
            for el in group:
                if el.get("class"):
                    found.append(Proxy(el, group.get("name"), path))
    return found


def pvpython_name(label):
    """The name paraview.simple gives a proxy or property of this label."""
    return re.sub(r"[^A-Za-z0-9_]", "", label)


def settings_markdown(p):
    """The settings of one proxy, MyST Markdown: a definition list, one
    setting a term (panel label; pvpython and Python names; default)."""
    lines = [f"Settings of *{p.label}* (Python: `{p.cls}`, pvpython: `{pvpython_name(p.label)}`). "
             "Each gives its panel label, then its pvpython property and Python method, then its default.", ""]
    for s in p.settings:
        if s.information_only:
            continue
        python = f"`{s.setter}`" if s.setter else ("`SetInputArrayToProcess`"
                                                   if s.command == "SetInputArrayToProcess" else "")
        default = s.default_text()
        if s.python_default is not None:
            default = f"{s.python_default_text()} in Python, {default} in the panel"
        names = ", ".join(x for x in (f"`{pvpython_name(s.label)}`", python) if x)
        term = f"**{s.label}** ({names}" + (f"; default: {default}" if default else "") + ")"
        what = s.doc or "(no description)"
        if s.entries:
            what += " Values: " + ", ".join(f"{text} ({v})" for v, text in s.entries) + "."
        if s.advanced:
            what += " *Advanced* (the panel's gear button)."
        lines += [term, f": {what}", ""]
    return "\n".join(lines)


def write_if_changed(path, text):
    """Writes text to path unless it holds it already (Sphinx then rebuilds only what changed)."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    if not os.path.exists(path) or open(path, encoding="utf-8").read() != text:
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)


def write_markdown(directory):
    """One settings file per proxy: <directory>/<Proxy>.md."""
    for p in proxies():
        write_if_changed(os.path.join(directory, p.name + ".md"), settings_markdown(p))


# ---- the headers' setter comments ------------------------------------------------------------

def header_of(cls):
    for d in HEADER_DIRS:
        path = os.path.join(d, cls + ".h")
        if os.path.exists(path):
            return path
    return None


def setter_line(lines, setting):
    """Index of the line declaring Set<setting> directly (not inside a macro), or None."""
    pattern = re.compile(r"^\s*(vtkSet\w*Macro\(\s*%s\s*,|(virtual\s+)?void\s+Set%s\s*\()" % (setting, setting))
    for i, line in enumerate(lines):
        if pattern.match(line) and not line.rstrip().endswith("\\"):
            return i
    return None


def comment_for(s, indent):
    text = s.doc
    default = s.python_default_text()
    if default and not s.entries:
        text += f" Default: {default}."
    elif default:
        text += " Values: " + ", ".join(f"{v} {t}" for v, t in s.entries) + f". Default: {default}."
    if s.python_default is not None:
        text += f" (The ParaView panel starts at {s.default_text()}: {s.python_default_reason})"
    width = 100 - len(indent) - 4
    return [f"{indent}/// {line}" for line in textwrap.wrap(text, width, break_on_hyphens=False)]


def header_changes():
    """{header path: (old lines, new lines)} for every header whose setter comments differ from the XML."""
    changes = {}
    seen = {}
    for p in proxies():
        path = header_of(p.cls)
        if path is None:
            continue
        if path not in changes:
            original = open(path, encoding="utf-8").read().split("\n")
            changes[path] = (original, list(original))
        lines = changes[path][1]
        for s in p.settings:
            if not s.setter or not s.doc:
                continue
            i = setter_line(lines, s.setter[3:])
            if i is None:
                continue
            key = (path, s.setter)
            if key in seen and seen[key] != s.doc:
                raise SystemExit(f"{path}: {s.setter} is documented differently by two proxies")
            seen[key] = s.doc
            indent = re.match(r"\s*", lines[i]).group(0)
            start = i
            while start > 0 and lines[start - 1].strip().startswith("///") \
                    and lines[start - 1].strip() not in ("///@{", "///@}"):
                start -= 1
            lines[start:i] = comment_for(s, indent)
    return {path: pair for path, pair in changes.items() if pair[0] != pair[1]}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--check-headers", action="store_true", help="list headers whose setter comments differ")
    parser.add_argument("--write-headers", action="store_true", help="rewrite the setter comments from the XML")
    parser.add_argument("--markdown", metavar="DIR", help="write the settings tables into DIR")
    args = parser.parse_args()
    if args.markdown:
        write_markdown(args.markdown)
    changes = header_changes() if (args.check_headers or args.write_headers) else {}
    for path, (_, new) in changes.items():
        if args.write_headers:
            with open(path, "w", encoding="utf-8") as f:
                f.write("\n".join(new))
        print(("rewrote " if args.write_headers else "FAILED: differs from the XML: ") + os.path.relpath(path, ROOT))
    if args.check_headers and changes:
        print("run: python3 docs/reference.py --write-headers")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
