"""Regression image: the demo's mean-curvature rendering of the bunny against
the baseline in Testing/Baseline (VTK-style image difference).
Run with --make-baseline to regenerate it (look at it before committing)."""
import os
import sys
import tempfile

from vtkmodules.vtkImagingCore import vtkImageDifference
from vtkmodules.vtkIOImage import vtkPNGReader, vtkPNGWriter

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Examples"))
import curvature_demo  # noqa: E402

BASELINE = os.path.join(HERE, "..", "Baseline", "bunny00_mean_curvature.png")
THRESHOLD = 0.15  # vtkRegressionTestImage's default thresholded error

output, _ = curvature_demo.compute_curvatures(os.path.join(HERE, "..", "Data", "bunny00.off"))
out_dir = os.environ.get("BELTRAMI_TEST_OUTPUT_DIR", tempfile.gettempdir())
test_png = os.path.join(out_dir, "bunny00_mean_curvature.png")
image = curvature_demo.render_mean_curvature(output, test_png, size=(400, 400))
if "--make-baseline" in sys.argv:
    os.replace(test_png, BASELINE)
    print("wrote " + BASELINE)
    sys.exit(0)

baseline = vtkPNGReader()
baseline.SetFileName(BASELINE)
baseline.Update()
diff = vtkImageDifference()
diff.SetInputData(image)
diff.SetImageData(baseline.GetOutput())
diff.Update()
error = diff.GetThresholdedError()
print("thresholded image error %.4f (limit %.2f)" % (error, THRESHOLD))
if error > THRESHOLD:
    writer = vtkPNGWriter()
    writer.SetFileName(os.path.join(out_dir, "bunny00_mean_curvature.diff.png"))
    writer.SetInputConnection(diff.GetOutputPort())
    writer.Write()
    print("FAILED: rendering differs from the baseline; see %s" % out_dir)
    sys.exit(1)
