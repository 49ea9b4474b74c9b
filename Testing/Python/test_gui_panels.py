"""The plugin's panels in the real ParaView GUI (under Xvfb): gui_panels.py
applies every proxy and makes it the active source; this fails on any line
of the application's output that says "critical", "ERR|", "ERROR" or shows
a Python traceback (an XML element ParaView does not know, a decorator
mode it does not have, a property the panel cannot build)."""
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
BAD = re.compile(r"critical|ERR\||ERROR|Traceback|Error:", re.IGNORECASE)

env = dict(os.environ, PV_PLUGIN_PATH="", BELTRAMI_GUI_PANELS_DIR=HERE)
proc = subprocess.run(["xvfb-run", "-a", "paraview", "--dr", "--script=" + os.path.join(HERE, "gui_panels.py"),
                       "--exit"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                      timeout=600)
lines = proc.stdout.splitlines()
bad = [line for line in lines if BAD.search(line)]
built = [line for line in lines if line.startswith("GUI panel test: panels built for")]
for line in bad:
    print("FAILED: " + line)
if not built:
    print("FAILED: the script did not finish (exit %d); its output:\n%s" % (proc.returncode, proc.stdout[-4000:]))
    sys.exit(1)
print(built[0])
sys.exit(1 if bad else 0)
