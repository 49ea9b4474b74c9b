#include "vtkTetGenTetrahedralizer.h"

#include "vtkBeltramiSurface.h"

#include "Core/ConjugateGradient.h"
#include "Core/Tetrahedra.h"

#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#define TETLIBRARY // Debian's libtet is built with it: errors are thrown, not exit()
#include <tetgen.h>

#include <limits>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkTetGenTetrahedralizer);

namespace
{
/// TetGen's exit codes (terminatetetgen) in words.
const char* TetGenReason(int code)
{
  switch (code)
  {
    case 1: return "out of memory";
    case 2: return "an internal error of TetGen";
    case 3: return "the surface intersects itself";
    case 4: return "a very small input feature size was detected (nearly touching parts)";
    case 5: return "two very close input facets were detected";
    case 10: return "an input error";
    default: return "an unknown error";
  }
}
} // namespace

std::string vtkTetGenTetrahedralizer::GetSwitches() const
{
  std::ostringstream s;
  s.precision(17);
  s << "pQz"; // a piecewise linear complex, quiet, ids from 0
  if (this->RadiusEdgeRatio > 0.0)
  {
    s << "q" << this->RadiusEdgeRatio;
    if (this->MinimumDihedralAngle > 0.0)
    {
      s << "/" << this->MinimumDihedralAngle;
    }
  }
  if (this->MaximumVolume > 0.0)
  {
    s << "a" << this->MaximumVolume;
  }
  if (this->PreserveSurface)
  {
    s << "Y";
  }
  return s.str();
}

int vtkTetGenTetrahedralizer::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

int vtkTetGenTetrahedralizer::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
  if (!input || !output)
  {
    vtkErrorMacro("Input must be vtkPolyData and output vtkUnstructuredGrid.");
    return 0;
  }
  output->Initialize(); // a defined output: empty
  const vtkIdType numPoints = input->GetNumberOfPoints();
  if (numPoints == 0)
  {
    return 1;
  }
  vtkBeltramiSurface surface;
  if (!surface.Build(input, 1))
  {
    vtkErrorMacro(<< surface.Error() << " The output is empty.");
    return 0;
  }
  const beltrami::MeshTopology& topo = surface.Topology();
  const beltrami::TopologySummary& info = topo.Summary();
  if (topo.NumberOfTriangles() == 0)
  {
    vtkErrorMacro("The input has no polygons: TetGen needs a closed surface. The output is empty.");
    return 0;
  }
  if (!info.IsClosed() || !info.IsManifold())
  {
    vtkErrorMacro("TetGen needs a closed manifold surface; the input has "
      << info.NumberOfBoundaryEdges << " boundary edges in " << info.NumberOfBoundaryLoops
      << " loops, " << info.NumberOfNonManifoldEdges << " non-manifold edges and "
      << info.NumberOfDuplicateTriangles << " duplicate triangles. The output is empty.");
    return 0;
  }
  std::vector<double> storage;
  const double* points = surface.PointsAsDouble(storage);
  for (vtkIdType k = 0; k < 3 * numPoints; ++k)
  {
    if (!std::isfinite(points[k]))
    {
      vtkErrorMacro("The input has NaN or infinite point coordinates. The output is empty.");
      return 0;
    }
  }
  if (numPoints > std::numeric_limits<int>::max() / 4)
  {
    vtkErrorMacro("Too many points for TetGen (" << numPoints << "). The output is empty.");
    return 0;
  }

  tetgenio in, out;
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(numPoints);
  in.pointlist = new REAL[3 * numPoints];
  std::copy(points, points + 3 * numPoints, in.pointlist);
  const beltrami::IndexArray& triangles = topo.TriangleList();
  const int numFacets = static_cast<int>(triangles.size() / 3);
  in.numberoffacets = numFacets;
  in.facetlist = new tetgenio::facet[numFacets];
  for (int f = 0; f < numFacets; ++f)
  {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k)
    {
      facet.polygonlist[0].vertexlist[k] = triangles[3 * f + k];
    }
  }

  // First TetGen's self-intersection check (-d): it returns the offending
  // facets instead of throwing.  libtet 1.5 frees its memory pools twice when
  // it throws from a self-intersecting input, so that case must never reach
  // the tetrahedralization.
  this->UpdateProgress(0.0);
  {
    tetgenio check;
    char detect[] = "pdQz";
    try
    {
      tetrahedralize(detect, &in, &check);
    }
    catch (int code)
    {
      check.initialize();
      vtkErrorMacro("TetGen's self-intersection check failed: " << TetGenReason(code) << " (code " << code
                                                                << "). The output is empty.");
      return 0;
    }
    if (check.numberoftrifaces > 0)
    {
      vtkErrorMacro("The surface intersects itself: TetGen found " << check.numberoftrifaces
                                                                  << " intersecting triangles. The output is empty.");
      return 0;
    }
  }
  this->UpdateProgress(0.2);
  const std::string switches = this->GetSwitches();
  std::vector<char> buffer(switches.begin(), switches.end());
  buffer.push_back('\0');
  try
  {
    tetrahedralize(buffer.data(), &in, &out);
  }
  catch (int code)
  {
    // The output may point into TetGen's freed pools after the throw: forget
    // it rather than free it twice (a small leak on an error path).
    out.initialize();
    vtkErrorMacro("TetGen failed: " << TetGenReason(code) << " (code " << code << ", switches '"
                                    << switches << "'). The output is empty.");
    return 0;
  }
  catch (const std::bad_alloc&)
  {
    out.initialize();
    vtkErrorMacro("TetGen ran out of memory. The output is empty.");
    return 0;
  }
  if (out.numberoftetrahedra <= 0 || out.numberofpoints <= 0 || out.numberofcorners < 4)
  {
    vtkErrorMacro("TetGen produced no tetrahedra (switches '" << switches << "'). The output is empty.");
    return 0;
  }

  vtkNew<vtkPoints> outPoints;
  outPoints->SetDataTypeToDouble();
  outPoints->SetNumberOfPoints(out.numberofpoints);
  std::copy(out.pointlist, out.pointlist + 3 * static_cast<std::size_t>(out.numberofpoints),
    vtkDoubleArray::SafeDownCast(outPoints->GetData())->GetPointer(0));
  output->SetPoints(outPoints);

  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(out.numberoftetrahedra + 1);
  connectivity->SetNumberOfValues(4 * static_cast<vtkIdType>(out.numberoftetrahedra));
  for (int t = 0; t < out.numberoftetrahedra; ++t)
  {
    offsets->SetValue(t, 4 * static_cast<vtkIdType>(t));
    for (int k = 0; k < 4; ++k)
    {
      connectivity->SetValue(4 * static_cast<vtkIdType>(t) + k, out.tetrahedronlist[t * out.numberofcorners + k]);
    }
  }
  offsets->SetValue(out.numberoftetrahedra, 4 * static_cast<vtkIdType>(out.numberoftetrahedra));
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  output->SetCells(VTK_TETRA, cells);

  this->InterpolatePointData(input->GetPointData(), numPoints, output, connectivity);
  vtkNew<vtkStringArray> used;
  used->SetName("TetGenSwitches");
  used->InsertNextValue(switches);
  output->GetFieldData()->AddArray(used);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkTetGenTetrahedralizer::InterpolatePointData(
  vtkPointData* inPD, vtkIdType numInput, vtkUnstructuredGrid* output, vtkIdTypeArray* connectivity)
{
  const vtkIdType numOutput = output->GetNumberOfPoints();
  std::vector<vtkDataArray*> arrays;
  int columns = 0;
  for (int a = 0; a < inPD->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = inPD->GetArray(a);
    if (array && array->GetNumberOfTuples() == numInput)
    {
      arrays.push_back(array);
      columns += array->GetNumberOfComponents();
    }
  }
  if (arrays.empty())
  {
    return;
  }
  // The input points come first and keep their values; the new (Steiner)
  // points get the harmonic extension: (K u)_i = 0 with the volume Laplacian
  // K of the output, exact for linear fields (linear precision).
  std::vector<double> values(static_cast<std::size_t>(numOutput) * columns, 0.0);
  {
    int slot = 0;
    for (vtkDataArray* array : arrays)
    {
      for (vtkIdType i = 0; i < numInput; ++i)
      {
        for (int c = 0; c < array->GetNumberOfComponents(); ++c)
        {
          values[i * columns + slot + c] = array->GetComponent(i, c);
        }
      }
      slot += array->GetNumberOfComponents();
    }
  }
  if (numOutput > numInput)
  {
    std::vector<beltrami::Index> tets(connectivity->GetPointer(0),
      connectivity->GetPointer(0) + connectivity->GetNumberOfValues());
    const beltrami::TetrahedralMesh mesh(static_cast<beltrami::Index>(numOutput), std::move(tets));
    std::vector<double> points(3 * static_cast<std::size_t>(numOutput));
    for (vtkIdType i = 0; i < numOutput; ++i)
    {
      output->GetPoint(i, &points[3 * i]);
    }
    beltrami::GraphLaplacian laplacian;
    beltrami::AssembleTetrahedralLaplacian(mesh, points.data(), 3, laplacian);
    std::vector<std::uint8_t> fixed(numOutput, 0);
    std::fill(fixed.begin(), fixed.begin() + numInput, 1);
    const std::vector<double> zero(values.size(), 0.0);
    for (int first = 0; first < columns; first += 8) // the solver takes up to 8 columns
    {
      const int nc = std::min(8, columns - first);
      std::vector<double> x(static_cast<std::size_t>(numOutput) * nc);
      for (vtkIdType i = 0; i < numOutput; ++i)
      {
        std::copy(&values[i * columns + first], &values[i * columns + first] + nc, &x[i * nc]);
      }
      beltrami::ConjugateGradientProblem pb;
      pb.Rows = numOutput;
      pb.Columns = nc;
      pb.Diagonal = laplacian.Diagonal.data();
      pb.Fixed = fixed.data();
      pb.Scale.assign(nc, 1.0);
      pb.Tolerance = 1e-12;
      pb.MaximumIterations = 5000;
      pb.Apply = [&](const double* in, double* out) { laplacian.ApplyStiffness(in, out, nc, 0); };
      beltrami::SolveConjugateGradient(pb, zero.data(), x.data());
      for (vtkIdType i = numInput; i < numOutput; ++i)
      {
        std::copy(&x[i * nc], &x[i * nc] + nc, &values[i * columns + first]);
      }
    }
  }
  int slot = 0;
  vtkPointData* outPD = output->GetPointData();
  for (vtkDataArray* array : arrays)
  {
    const int nc = array->GetNumberOfComponents();
    auto result = vtk::TakeSmartPointer(array->NewInstance());
    result->SetName(array->GetName());
    result->SetNumberOfComponents(nc);
    result->SetNumberOfTuples(numOutput);
    for (vtkIdType i = 0; i < numOutput; ++i)
    {
      for (int c = 0; c < nc; ++c)
      {
        result->SetComponent(i, c, values[i * columns + slot + c]);
      }
    }
    slot += nc;
    outPD->AddArray(result);
    if (array == inPD->GetScalars())
    {
      outPD->SetActiveScalars(result->GetName());
    }
  }
}

void vtkTetGenTetrahedralizer::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "RadiusEdgeRatio: " << this->RadiusEdgeRatio << "\n";
  os << indent << "MinimumDihedralAngle: " << this->MinimumDihedralAngle << "\n";
  os << indent << "MaximumVolume: " << this->MaximumVolume << "\n";
  os << indent << "PreserveSurface: " << this->PreserveSurface << "\n";
}
