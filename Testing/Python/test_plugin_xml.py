"""Every property of the ParaView proxies (ParaViewPlugin/*.xml) against the
filter it drives, through the Python wrapping: the command exists, the XML
default equals the filter's own default (what a Python user gets), every
value of an enumeration is one the filter keeps (not clamped away), and the
filter accepts no value beyond the enumeration's (a missing GUI option).
PrintSelf must name every property's setting.  Prints FAILED lines and exits
1 on any mismatch."""
import glob
import os
import sys
import xml.etree.ElementTree as ET

import beltrami

HERE = os.path.dirname(os.path.abspath(__file__))
PLUGIN = os.path.join(HERE, "..", "..", "ParaViewPlugin")
# Commands that are not plain Set/Get pairs on the filter.
SKIP_COMMANDS = {"SetInputArrayToProcess", "SetInputConnection", "AddInputConnection", "SetFileName",
                 "AddFixedPoint", "RemoveAllFixedPoints", "AddPointConstraint", "RemoveAllPointConstraints",
                 "AddShortestPathLineConstraint", "AddBoundaryHandle", "AddTransferFunctionPoint"}
problems = []
checked = {"properties": 0, "defaults": 0, "enumerations": 0}


def fail(text):
    problems.append(text)
    print("FAILED:", text)


def values_of(prop, kind, attribute="default_values"):
    text = prop.get(attribute)
    if text is None:
        return None
    if kind == "StringVectorProperty" and text == "":
        return [""]
    convert = {"IntVectorProperty": int, "DoubleVectorProperty": float, "StringVectorProperty": str}[kind]
    return [convert(v) for v in text.split()]


def getter_value(obj, command, count):
    get = getattr(obj, "G" + command[1:], None)
    if get is None:
        return None
    value = get()
    if isinstance(value, (tuple, list)):
        return list(value)
    return [value] if count == 1 else None


def same(a, b):
    if len(a) != len(b):
        return False
    for x, y in zip(a, b):
        if isinstance(x, float) or isinstance(y, float):
            if abs(float(x) - float(y)) > 1e-12 * max(1.0, abs(float(x))):
                return False
        elif x != y:
            return False
    return True


def check_enumeration(obj, proxy, name, command, prop):
    entries = [int(e.get("value")) for e in prop.iter("Entry")]
    set_ = getattr(obj, command)
    get = getattr(obj, "G" + command[1:], None)
    if get is None or not entries:
        return
    checked["enumerations"] += 1
    original = get()
    for v in entries:
        set_(v)
        if get() != v:
            fail(f"{proxy}.{name}: enumeration value {v} is changed to {get()} by {command}")
    for v in (min(entries) - 1, max(entries) + 1):
        set_(v)
        if get() == v:
            fail(f"{proxy}.{name}: the filter accepts {v}, which the XML enumeration does not offer")
    set_(original)


def check_proxy(proxy_el, file):
    cls = proxy_el.get("class")
    proxy = proxy_el.get("name")
    if not cls or not hasattr(beltrami, cls):
        return
    obj = getattr(beltrami, cls)()
    printed = str(obj)
    for prop in proxy_el:
        kind = prop.tag
        if kind not in ("IntVectorProperty", "DoubleVectorProperty", "StringVectorProperty"):
            continue
        command = prop.get("command")
        name = prop.get("name")
        if not command or command in SKIP_COMMANDS or prop.get("information_only") == "1":
            continue
        checked["properties"] += 1
        if not hasattr(obj, command):
            fail(f"{file}: {proxy}.{name}: {cls} has no {command}")
            continue
        count = int(prop.get("number_of_elements", "1"))
        default = values_of(prop, kind)
        if default is not None and prop.get("repeat_command") != "1":
            actual = getter_value(obj, command, count)
            if actual is None:
                fail(f"{file}: {proxy}.{name}: {cls} has no getter for {command} to compare the default with")
            else:
                checked["defaults"] += 1
                # A deliberate difference is said in the XML itself (the one
                # source of the reference, docs/reference.py).
                hint = prop.find("Hints/PythonDefault")
                if hint is not None:
                    python_default = values_of(hint, kind, "value")
                    if same(default, actual) or not same(python_default, actual):
                        fail(f"{file}: {proxy}.{name}: the XML says Python starts at {python_default} "
                             f"and the panel at {default}, but {cls} starts at {actual}")
                elif not same(default, actual):
                    fail(f"{file}: {proxy}.{name}: XML default {default} but {cls} starts at {actual}")
        if prop.find("EnumerationDomain") is not None:
            check_enumeration(obj, proxy, name, command, prop)
        setting = command[3:] if command.startswith("Set") else command
        # A setting renamed for consistency keeps its old XML name (the key of
        # state files) and shows the new name: the label must be the setting.
        if setting != name and command != "SetInputArrayToProcess":
            label = (prop.get("label") or "").replace(" ", "")
            if label != setting:
                fail(f"{file}: {proxy}.{name}: calls {command}; its label must be the setting's name "
                     f"(spaced), not '{prop.get('label')}'")
        if setting not in printed:
            fail(f"{file}: {proxy}.{name}: {cls}::PrintSelf does not list {setting}")


def main():
    files = sorted(glob.glob(os.path.join(PLUGIN, "*.xml")))
    if len(files) < 2:
        fail(f"no plugin XML files under {PLUGIN}")
    for path in files:
        root = ET.parse(path).getroot()
        for el in root.iter():
            if el.tag in ("SourceProxy", "Proxy", "WriterProxy"):
                check_proxy(el, os.path.basename(path))
    print(f"{checked['properties']} properties, {checked['defaults']} defaults, "
          f"{checked['enumerations']} enumerations checked in {len(files)} files")
    if checked["properties"] < 50:
        fail("too few properties checked: the XML was not read")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
