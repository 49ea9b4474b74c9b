"""Run inside the ParaView GUI (paraview --script=gui_panels.py): every
proxy of the plugin (ParaViewPlugin/*.xml) applied to suitable data and made
the active source, so that the Properties panel builds its widgets, domains
and decorators (the advanced ones too, hidden).  test_gui_panels.py reads
what the application printed."""
import glob
import os
import xml.etree.ElementTree as ET

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager

HERE = os.environ["BELTRAMI_GUI_PANELS_DIR"]  # (the GUI runs this without __file__)
PLUGIN_XML = os.path.join(HERE, "..", "..", "ParaViewPlugin")
DATA = os.path.join(HERE, "..", "Data")

LoadPlugin(os.environ["BELTRAMI_PLUGIN"], ns=globals())



def proxy_function(proxy):
    """The paraview.simple function of an XML proxy: its label (or name)
    made a valid Python name."""
    return globals().get(servermanager._make_name_valid(proxy.get("label") or proxy.get("name")))


# Suitable data: each with a point array for the filters that smooth or
# differentiate one (the surface also with a vector array).
surface = Calculator(Input=Elevation(Input=OpenDataFile(os.path.join(DATA, "eight.off"))), ResultArrayName="Wind",
                     Function="coordsY*iHat - coordsX*jHat")
image = Wavelet(WholeExtent=[0, 15, 0, 15, 0, 15])
volume = Elevation(Input=TetGenTetrahedralize(Input=surface))
inputs = {"vtkPolyData": surface, "vtkImageData": image, "vtkUnstructuredGrid": volume}
for data in inputs.values():
    data.UpdatePipeline()  # (as after Apply: the array lists of the filters below see their arrays)
readers = {"OFFReader": os.path.join(DATA, "eight.off")}

done = []
proxies = [proxy for path in sorted(glob.glob(os.path.join(PLUGIN_XML, "*.xml")))
           for group in ET.parse(path).getroot().iter("ProxyGroup") if group.get("name") in ("filters", "sources")
           for proxy in group.iter("SourceProxy")]
for proxy in proxies:
    name = proxy.get("name")
    maker = proxy_function(proxy)
    if maker is None:
        print("GUI panel test: ERROR no proxy function for %s" % name)
        continue
    if proxy.find(".//ReaderFactory") is not None:
        if name not in readers:
            continue  # a reader of files the tests do not make here (OpenVDB: test_openvdb.py)
        source = OpenDataFile(readers[name])
    else:
        types = [d.get("value") for d in proxy.iter("DataType")]
        SetActiveSource(inputs[types[0]])  # as a user: select the input, then the filter
        source = maker(Input=inputs[types[0]])
    SetActiveSource(source)
    Show(source)
    Render()
    done.append(name)
print("GUI panel test: panels built for " + " ".join(done))
