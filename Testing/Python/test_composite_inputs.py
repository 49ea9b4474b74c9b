"""Every surface filter on a composite input (a vtkMultiBlockDataSet of two
surfaces, as ParaView's readers and Group Datasets give): no error, each
block's output the one the filter gives for that block alone, and the
second outputs (the atlas's and the remesher's maps, the line drawing's
surface) one per block."""
import sys
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet, vtkMultiBlockDataSet
from vtkmodules.vtkFiltersSources import vtkSphereSource

import inputs
from test_hostile_inputs import filters

# The filters that take a surface and need nothing else set; the vector
# field decomposition gets the surfaces with a vector array.
SURFACE_FILTERS = ["curvatures", "fairing", "parameterization", "atlas", "remeshing", "remeshing-anisotropic",
                   "line-drawing", "vector-fields", "tetgen"]


def sphere(radius, centre, open_cap):
    """A sphere, or (open_cap) a cap of it: a disk, which the
    parameterization takes."""
    s = vtkSphereSource()
    s.SetRadius(radius)
    s.SetCenter(centre)
    s.SetThetaResolution(24)
    s.SetPhiResolution(16)
    if open_cap:
        s.SetEndPhi(120.0)
    s.Update()
    return s.GetOutput()


def blocks(name):
    """Two surfaces of different sizes, as they go into the filter."""
    open_cap = name == "parameterization"
    surfaces = [sphere(1.0, (0.0, 0.0, 0.0), open_cap), sphere(0.5, (3.0, 0.0, 0.0), open_cap)]
    return [inputs.with_vectors(s) if name == "vector-fields" else s for s in surfaces]


def run(name, data):
    """(the filter after its run, its errors)."""
    f = filters()[name][0]()
    said = inputs.Messages(f, f.GetExecutive())
    f.SetInputData(data)
    f.Update()
    return f, said.errors


def points(data):
    return vtk_to_numpy(data.GetPoints().GetData()) if data.GetNumberOfPoints() else np.zeros((0, 3))


class CompositeInputs(unittest.TestCase):
    def test_every_surface_filter(self):
        for name in SURFACE_FILTERS:
            with self.subTest(filter=name):
                parts = blocks(name)
                group = vtkMultiBlockDataSet()
                group.SetNumberOfBlocks(len(parts))
                for b, part in enumerate(parts):
                    group.SetBlock(b, part)
                f, errors = run(name, group)
                self.assertEqual(errors, [])
                for port in range(f.GetNumberOfOutputPorts()):
                    out = f.GetOutputDataObject(port)
                    self.assertIsInstance(out, vtkCompositeDataSet, "output %d" % port)
                    self.assertEqual(out.GetNumberOfBlocks(), len(parts), "output %d" % port)
                for b, part in enumerate(parts):
                    alone, errors = run(name, part)
                    self.assertEqual(errors, [])
                    for port in range(f.GetNumberOfOutputPorts()):
                        mine, theirs = f.GetOutputDataObject(port).GetBlock(b), alone.GetOutputDataObject(port)
                        self.assertEqual(mine.GetClassName(), theirs.GetClassName())
                        if isinstance(theirs, vtkCompositeDataSet):
                            self.assertGreater(theirs.GetNumberOfBlocks(), 0)
                            self.assertEqual(mine.GetNumberOfBlocks(), theirs.GetNumberOfBlocks())
                        else:
                            self.assertGreater(theirs.GetNumberOfPoints(), 0)
                            np.testing.assert_allclose(points(mine), points(theirs), rtol=0, atol=1e-12)
        print("composite inputs test passed")
        sys.stdout.flush()


if __name__ == "__main__":
    unittest.main()
