"""Regression images (VTK-style image difference against Testing/Baseline):
the demo's mean-curvature rendering of the bunny, and the mushroom with a
checkerboard mapped by its natural conformal parameterization.
Run with --make-baseline to regenerate them (look at them before committing)."""
import os
import sys
import tempfile

from vtkmodules.vtkImagingCore import vtkImageDifference
from vtkmodules.vtkIOImage import vtkPNGReader, vtkPNGWriter

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Examples"))
import curvature_demo  # noqa: E402
import parameterization_demo  # noqa: E402

THRESHOLD = 0.15  # vtkRegressionTestImage's default thresholded error
DATA = os.path.join(HERE, "..", "Data")
out_dir = os.environ.get("BELTRAMI_TEST_OUTPUT_DIR", tempfile.gettempdir())


def compare(name, render):
    """Renders into out_dir/name and compares with the baseline of that name."""
    baseline_png = os.path.join(HERE, "..", "Baseline", name)
    test_png = os.path.join(out_dir, name)
    image = render(test_png)
    if "--make-baseline" in sys.argv:
        os.replace(test_png, baseline_png)
        print("wrote " + baseline_png)
        return True
    baseline = vtkPNGReader()
    baseline.SetFileName(baseline_png)
    baseline.Update()
    diff = vtkImageDifference()
    diff.SetInputData(image)
    diff.SetImageData(baseline.GetOutput())
    diff.Update()
    error = diff.GetThresholdedError()
    print("%s: thresholded image error %.4f (limit %.2f)" % (name, error, THRESHOLD))
    if error > THRESHOLD:
        writer = vtkPNGWriter()
        writer.SetFileName(os.path.join(out_dir, name.replace(".png", ".diff.png")))
        writer.SetInputConnection(diff.GetOutputPort())
        writer.Write()
        print("FAILED: %s differs from the baseline; see %s" % (name, out_dir))
        return False
    return True


curvatures, _ = curvature_demo.compute_curvatures(os.path.join(DATA, "bunny00.off"))
natural, _ = parameterization_demo.parameterize(os.path.join(DATA, "mushroom.off"))
ok = compare("bunny00_mean_curvature.png",
             lambda png: curvature_demo.render_mean_curvature(curvatures, png, size=(400, 400)))
ok = compare("mushroom_checkerboard.png",
             lambda png: parameterization_demo.render_checkerboard(natural.GetOutput(), png,
                                                                   size=(400, 400))) and ok
sys.exit(0 if ok else 1)
