# Sources, vortices and circulation of a field on a torus: the Helmholtz-Hodge
# decomposition (thesis section 6.3).
import numpy as np
from beltrami import vtkSurfaceVectorFieldDecomposition
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy

# A torus about z (radii 1 and 0.4), 200 x 80 points.
nu, nv = 200, 80
u, v = np.meshgrid(np.linspace(0, 2 * np.pi, nu, endpoint=False), np.linspace(0, 2 * np.pi, nv, endpoint=False),
                   indexing="ij")
p = np.stack([(1 + 0.4 * np.cos(v)) * np.cos(u), (1 + 0.4 * np.cos(v)) * np.sin(u), 0.4 * np.sin(v)], axis=-1)
i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
a, b, c, d = i * nv + j, (i + 1) % nu * nv + j, (i + 1) % nu * nv + (j + 1) % nv, i * nv + (j + 1) % nv
triangles = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
surface = vtkPolyData()
surface.SetPoints(vtkPoints())
surface.GetPoints().SetData(numpy_to_vtk(p.reshape(-1, 3), deep=True))
cells = vtkCellArray()
cells.SetData(3, numpy_to_vtkIdTypeArray(triangles.ravel().astype(np.int64), deep=True))
surface.SetPolys(cells)

# A flow around the axis (harmonic on the torus), a source at +x, a vortex at -x.
p = p.reshape(-1, 3)
around = np.stack([-p[:, 1], p[:, 0], 0 * p[:, 0]], axis=1) / (p[:, 0:1] ** 2 + p[:, 1:2] ** 2)
bump = np.exp(-4 * ((p[:, 0:1] - 1.2) ** 2 + p[:, 1:2] ** 2))
swirl = np.exp(-4 * ((p[:, 0:1] + 1.2) ** 2 + p[:, 1:2] ** 2))
field = around + bump * (p - [1.2, 0, 0]) + swirl * np.cross([0, 0, 1], p - [-1.2, 0, 0])
array = numpy_to_vtk(field, deep=True)
array.SetName("Wind")
surface.GetPointData().AddArray(array)

decomposition = vtkSurfaceVectorFieldDecomposition()
decomposition.SetInputData(surface)
decomposition.SetInputArrayToProcess(0, 0, 0, 0, "Wind")  # 0: point data
decomposition.Update()
out = decomposition.GetOutput()

energy = {name: out.GetFieldData().GetArray(name + "Energy").GetValue(0)
          for name in ("Tangent", "CurlFree", "DivergenceFree", "Harmonic")}
print("shares of the energy: curl-free %.3f, divergence-free %.3f, harmonic %.3f"
      % tuple(energy[k] / energy["Tangent"] for k in ("CurlFree", "DivergenceFree", "Harmonic")))
divergence = vtk_to_numpy(out.GetPointData().GetArray("Divergence"))
print("strongest source at", p[np.nanargmax(divergence)].round(2))
curl = vtk_to_numpy(out.GetPointData().GetArray("Curl"))
print("strongest vortex at", p[np.nanargmax(np.abs(curl))].round(2))
