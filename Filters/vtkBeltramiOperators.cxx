#include "vtkBeltramiOperators.h"
#include "vtkBeltramiSettings.h"

#include "vtkBeltramiGather.h"
#include "vtkBeltramiGraphFlow.h"
#include "vtkBeltramiPieces.h"
#include "vtkBeltramiSurface.h"

#include "Flows/GraphOperators.h"
#include "Mesh/Tetrahedra.h"

#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkBeltramiOperators);

BELTRAMI_SAME_ENUM(vtkBeltramiOperators::REFLECT, beltrami::GridBoundary::Reflect);
BELTRAMI_SAME_ENUM(vtkBeltramiOperators::LINEAR, beltrami::GridBoundary::Linear);

namespace
{

/// The data array (input array 0 of `self` on `input`) as doubles
/// (components per point), or an error on `self`.
bool ReadData(vtkBeltramiOperators* self, vtkDataArray* array, int association, vtkDataSet* input, int maximum,
  std::vector<double>& values, int& nc)
{
  if (!array || association != vtkDataObject::FIELD_ASSOCIATION_POINTS)
  {
    vtkErrorWithObjectMacro(self, "No point array to take as a graph: select a point data array (input array 0). "
                                  "The output is the input.");
    return false;
  }
  nc = array->GetNumberOfComponents();
  if (nc < 1 || nc > maximum)
  {
    vtkErrorWithObjectMacro(self, "The array '" << (array->GetName() ? array->GetName() : "") << "' has " << nc
      << " components; 1 to " << maximum << " are supported here. The output is the input.");
    return false;
  }
  const vtkIdType n = input->GetNumberOfPoints();
  values.resize(static_cast<std::size_t>(n) * nc);
  vtkIdType nonFinite = 0;
  for (vtkIdType i = 0; i < n; ++i)
  {
    array->GetTuple(i, &values[static_cast<std::size_t>(i) * nc]);
    for (int k = 0; k < nc; ++k)
    {
      if (!std::isfinite(values[static_cast<std::size_t>(i) * nc + k]))
      {
        ++nonFinite;
        break;
      }
    }
  }
  if (nonFinite > 0)
  {
    vtkWarningWithObjectMacro(self, << nonFinite << " points have NaN or infinite values: the operators "
                                    << "next to them are not finite.");
  }
  return true;
}

/// The core's output buffers for the switched-on arrays.
struct Maps
{
  std::vector<double> Normal, Beltrami, Mean, Gauss, Indicator;
  std::vector<std::uint8_t> Undefined; ///< per core vertex: the operators are not defined there (NaN by design)
  int Base = 3, Components = 1;
  bool Gaussian = true;

  beltrami::GraphOperatorOutputs Allocate(vtkBeltramiOperators* f, vtkIdType n, int base, int nc, bool gaussian)
  {
    Base = base;
    Components = nc;
    Gaussian = gaussian && f->GetComputeGaussianCurvature();
    const auto take = [n](bool on, std::vector<double>& v, int width) {
      v.assign(on ? static_cast<std::size_t>(n) * width : 0, 0.0);
      return on ? v.data() : nullptr;
    };
    beltrami::GraphOperatorOutputs out;
    out.MeanCurvatureNormal = take(f->GetComputeMeanCurvatureNormal(), Normal, base + nc);
    out.BeltramiOperator = take(f->GetComputeBeltramiOperator(), Beltrami, nc);
    out.MeanCurvature = take(f->GetComputeMeanCurvature(), Mean, 1);
    out.GaussianCurvature = take(Gaussian, Gauss, 1);
    out.EdgeIndicator = take(f->GetComputeEdgeIndicator(), Indicator, 1);
    Undefined.assign(static_cast<std::size_t>(n), 0);
    out.Undefined = Undefined.data();
    return out;
  }

  /// Adds the arrays to `output`: its point o takes the core's vertex
  /// source(o); the normal's base components go to the VTK axes `axes`.
  /// Returns the number of points given a NaN or infinite value where the
  /// operators are defined (not at boundary points: NaN there by design).
  vtkIdType AddTo(vtkDataSet* output, const std::function<vtkIdType(vtkIdType)>& source, const int* axes) const
  {
    const vtkIdType n = output->GetNumberOfPoints();
    std::vector<std::uint8_t> nonFinite(static_cast<std::size_t>(n), 0);
    vtkPointData* pd = output->GetPointData();
    const auto add = [&](const std::vector<double>& from, const char* name, int width, int outWidth,
                       const std::function<int(int)>& slot) {
      if (from.empty())
      {
        return;
      }
      vtkSmartPointer<vtkDataArray> a = vtkBeltramiSurface::NewArray(VTK_DOUBLE, name, outWidth, n);
      double* dst = static_cast<double*>(a->GetVoidPointer(0));
      std::fill(dst, dst + static_cast<std::size_t>(n) * outWidth, 0.0);
      for (vtkIdType o = 0; o < n; ++o)
      {
        const std::size_t row = static_cast<std::size_t>(source(o));
        const double* src = &from[row * width];
        for (int k = 0; k < width; ++k)
        {
          dst[static_cast<std::size_t>(o) * outWidth + slot(k)] = src[k];
          nonFinite[o] = nonFinite[o] || (!std::isfinite(src[k]) && !Undefined[row]);
        }
      }
      pd->AddArray(a);
    };
    const auto same = [](int k) { return k; };
    add(Normal, "MeanCurvatureNormal", Base + Components, 3 + Components,
      [&](int k) { return k < Base ? axes[k] : 3 + k - Base; });
    add(Beltrami, "BeltramiOperator", Components, Components, same);
    add(Mean, "MeanCurvature", 1, 1, same);
    add(Gauss, "GaussianCurvature", 1, 1, same);
    add(Indicator, "EdgeIndicator", 1, 1, same);
    return static_cast<vtkIdType>(std::count(nonFinite.begin(), nonFinite.end(), 1));
  }
};

/// A warning where operators came out NaN or infinite: beside data that
/// are, or where the data are so large that the metric's squares overflow.
void WarnNonFiniteOperators(vtkBeltramiOperators* self, vtkIdType points)
{
  if (points > 0)
  {
    vtkWarningWithObjectMacro(self, << points << " points have NaN or infinite operators: their data or their "
                                    << "neighbours' are NaN or infinite, or so large (beyond about 1e150) that the "
                                    << "graph metric's squares exceed the range of doubles.");
  }
}

void AddReport(vtkFieldData* fd, const beltrami::GraphOperatorReport& r)
{
  const auto add = [fd](const char* name, double value) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name);
    a->InsertNextValue(value);
    fd->AddArray(a);
  };
  add("GraphContrastScale", r.ContrastScale);
  add("GraphNoiseLevel", r.NoiseLevel);
  add("EstimatedNoiseLevel", r.EstimatedNoiseLevel);
  add("GraphUndefinedPoints", static_cast<double>(r.UndefinedVertices));
}

} // namespace

vtkBeltramiOperators::vtkBeltramiOperators()
{
  beltrami::GraphOperatorOptions defaults;
  this->CopySettings(defaults, vtkBeltramiCopy::FromCore);
  this->SetInputArrayToProcess(
    DATA_ARRAY, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

void vtkBeltramiOperators::CopySettings(beltrami::GraphOperatorOptions& o, vtkBeltramiCopy direction)
{
  BeltramiCopySetting(this->ContrastScale, o.ContrastScale, direction);
  BeltramiCopySetting(this->NoiseLevel, o.NoiseLevel, direction);
  BeltramiCopySetting(this->BoundaryHandling, o.Boundary, direction);
  BeltramiCopySetting(this->NumberOfThreads, o.NumberOfThreads, direction);
}

int vtkBeltramiOperators::FillInputPortInformation(int, vtkInformation* info)
{
  info->Remove(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE());
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  return 1;
}

int vtkBeltramiOperators::RequestInformation(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (vtkImageData::GetData(inputVector[0]))
  {
    // Any sub-extent can be produced (ParaView's pieces become extents).
    outputVector->GetInformationObject(0)->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  }
  return this->Superclass::RequestInformation(request, inputVector, outputVector);
}

int vtkBeltramiOperators::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (vtkImageData::GetData(inputVector[0]))
  {
    // One ring of neighbours, or all of the image for the noise estimate.
    vtkBeltramiGraphFlow::RequestImageExtent(inputVector[0]->GetInformationObject(0),
      outputVector->GetInformationObject(0), this->ContrastScale > 0.0 ? 1 : -1);
    return 1;
  }
  return this->Superclass::RequestUpdateExtent(request, inputVector, outputVector);
}

int vtkBeltramiOperators::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (vtkImageData* image = vtkImageData::GetData(inputVector[0]))
  {
    vtkImageData* output = vtkImageData::GetData(outputVector);
    int whole[6], outExt[6];
    inputVector[0]->GetInformationObject(0)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), outExt);
    return output ? this->RunImage(image, output, whole, outExt) : 0;
  }
  vtkBeltramiSurface::WarnNonFinitePoints(
    this, vtkDataSet::GetData(inputVector[0]), "the operators at them and next to them are not finite.");
  if (vtkPolyData::GetData(inputVector[0]))
  {
    // Local operators (1-rings), and the automatic contrast scale's noise
    // estimate and mean edge length taken over the ranks: split surfaces
    // stay distributed (pieces with ghost cells are gathered on rank 0),
    // and so do split tetrahedra below.
    return vtkBeltramiSurface::Execute(this, inputVector, outputVector, this->NumberOfThreads,
      vtkBeltramiSurface::Needs::Distributed,
      [this](vtkBeltramiSurface& surface) { return this->RunSurface(surface); });
  }
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0]);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
  if (!input || !output)
  {
    vtkErrorMacro("The input must be vtkImageData, vtkPolyData or vtkUnstructuredGrid.");
    return 0;
  }
  // The same for tetrahedra split over ranks that can talk (pieces without
  // ghost cells; every rank takes the same branch: the counts are collective).
  if (vtkBeltramiPieces::CanSolveTogether(outInfo) &&
    vtkBeltramiSurface::PiecesHoldingData(outInfo, input) > 1 && vtkBeltramiPieces::RingsAreMissing(input))
  {
    return this->RunMeshSplit(input, output);
  }
  return vtkBeltramiGather::RunWhole(outInfo, input, output, vtkBeltramiGather::Results::ToEveryPiece,
    [this](vtkPointSet* in, vtkPointSet* out, int holding) {
      return this->RunMesh(in, out, vtkUnstructuredGrid::SafeDownCast(in), holding);
    });
}

int vtkBeltramiOperators::RunMeshSplit(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output)
{
  output->ShallowCopy(input); // a defined output: the input
  vtkBeltramiPieces pieces;
  pieces.SetCollective(true);
  vtkBeltramiGraphFlow::SplitMesh mesh; // every point of the piece with its whole star
  if (!vtkBeltramiGraphFlow::SplitTetrahedra(this, input, pieces, true, this->NumberOfThreads, mesh))
  {
    return 0;
  }
  const beltrami::Partition* split = pieces.Split();
  if (split->Sum(mesh.OwnTetrahedra) == 0.0)
  {
    if (split->Rank() == 0)
    {
      vtkWarningMacro("The input has no tetrahedra or voxels: no operators.");
    }
    return 1;
  }
  std::vector<double> values;
  int nc = 0, association = -1;
  const bool empty = input->GetNumberOfPoints() == 0; // (it may lack the arrays)
  vtkDataArray* array = empty ? nullptr : this->GetInputArrayToProcess(DATA_ARRAY, input, association);
  if (!pieces.AllAgree(empty || ReadData(this, array, association, input, 6, values, nc)))
  {
    return 0;
  }
  nc = static_cast<int>(split->Max(nc));
  values.resize(static_cast<std::size_t>(split->Rows()) * nc);
  split->UpdateGhosts(values.data(), nc);
  beltrami::GraphOperatorOptions o;
  this->CopySettings(o, vtkBeltramiCopy::ToCore);
  Maps maps;
  const beltrami::GraphOperatorOutputs out = maps.Allocate(this, split->Rows(), 3, nc, false);
  const beltrami::GraphOperatorReport r =
    beltrami::ComputeTetrahedralGraphOperators(*mesh.Mesh, mesh.Points.data(), nc, values.data(), o, out, split);
  if (!r.Error.empty())
  {
    vtkErrorMacro(<< r.Error << ". The output is the input.");
    return 0;
  }
  const int axes[3] = { 0, 1, 2 };
  // (The piece's points: the ring's are dropped.)
  WarnNonFiniteOperators(this, maps.AddTo(output, [](vtkIdType i) { return i; }, axes) + r.OverflowVertices);
  AddReport(output->GetFieldData(), r);
  return 1;
}

bool vtkBeltramiOperators::RunSurface(vtkBeltramiSurface& surface)
{
  const beltrami::Partition* split = surface.Split(); // every rank runs, an empty piece's too
  const double triangles = static_cast<double>(surface.Topology().NumberOfTriangles());
  if ((split ? split->Sum(triangles) : triangles) == 0.0)
  {
    vtkWarningMacro("The input has no polygons or triangle strips: no operators.");
    return true;
  }
  if (!split) // (a split piece's own defects are those of its cut)
  {
    surface.WarnAboutInput(this, "a free boundary where pieces meet", "The operators are NaN there.");
  }
  std::vector<double> values, storage;
  int nc = 0, association = -1;
  const bool empty = split && surface.NumberOfInputPoints() == 0; // it may lack the arrays
  vtkDataArray* array = empty ? nullptr : this->GetInputArrayToProcess(DATA_ARRAY, surface.Input(), association);
  if (!surface.AllAgree(empty || ReadData(this, array, association, surface.Input(), 5, values, nc)))
  {
    return false;
  }
  const std::size_t rows = static_cast<std::size_t>(surface.NumberOfTopologyPoints());
  if (split)
  {
    nc = static_cast<int>(split->Max(nc));
    values.resize(rows * nc);
    split->UpdateGhosts(values.data(), nc);
  }
  beltrami::GraphOperatorOptions o;
  this->CopySettings(o, vtkBeltramiCopy::ToCore);
  Maps maps;
  const beltrami::GraphOperatorOutputs out = maps.Allocate(this, static_cast<vtkIdType>(rows), 3, nc, true);
  const beltrami::GraphOperatorReport r = beltrami::ComputeSurfaceGraphOperators(
    surface.Topology(), surface.PointsAsDouble(storage), nc, values.data(), o, out, split);
  if (!r.Error.empty())
  {
    vtkErrorMacro(<< r.Error << ". The output is the input.");
    return false;
  }
  const int axes[3] = { 0, 1, 2 };
  WarnNonFiniteOperators(this, maps.AddTo(surface.Output(), [](vtkIdType o) { return o; }, axes) + r.OverflowVertices);
  AddReport(surface.Output()->GetFieldData(), r);
  return true;
}

int vtkBeltramiOperators::RunMesh(vtkDataSet* input, vtkDataSet* output, vtkUnstructuredGrid* volume, int holding)
{
  output->ShallowCopy(input);
  if (!volume || input->GetNumberOfPoints() == 0)
  {
    return volume ? 1 : 0;
  }
  if (holding > 1)
  {
    vtkBeltramiSurface::WarnDistributed(this, holding, "a free boundary where pieces meet");
  }
  std::vector<beltrami::Index> tets = vtkBeltramiGraphFlow::Tetrahedra(this, volume);
  if (tets.empty())
  {
    vtkWarningMacro("The input has no tetrahedra or voxels: no operators.");
    return 1;
  }
  std::vector<double> values;
  int nc = 0, association = -1;
  vtkDataArray* array = this->GetInputArrayToProcess(DATA_ARRAY, input, association);
  if (!ReadData(this, array, association, input, 6, values, nc))
  {
    return 0;
  }
  const vtkIdType n = input->GetNumberOfPoints();
  const beltrami::TetrahedralMesh mesh(static_cast<beltrami::Index>(n), std::move(tets), this->NumberOfThreads);
  std::vector<double> points(3 * static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    input->GetPoint(i, &points[3 * i]);
  }
  beltrami::GraphOperatorOptions o;
  this->CopySettings(o, vtkBeltramiCopy::ToCore);
  Maps maps;
  const beltrami::GraphOperatorOutputs out = maps.Allocate(this, n, 3, nc, false);
  const beltrami::GraphOperatorReport r =
    beltrami::ComputeTetrahedralGraphOperators(mesh, points.data(), nc, values.data(), o, out);
  if (!r.Error.empty())
  {
    vtkErrorMacro(<< r.Error << ". The output is the input.");
    return 0;
  }
  const int axes[3] = { 0, 1, 2 };
  WarnNonFiniteOperators(this, maps.AddTo(output, [](vtkIdType i) { return i; }, axes) + r.OverflowVertices);
  AddReport(output->GetFieldData(), r);
  return 1;
}

int vtkBeltramiOperators::RunImage(vtkImageData* input, vtkImageData* output, const int* whole, const int* outExt)
{
  // A defined output first: the input, cropped to the requested extent.
  int inExt[6], ext[6];
  input->GetExtent(inExt);
  std::copy(outExt, outExt + 6, ext);
  output->ShallowCopy(input);
  if (!std::equal(inExt, inExt + 6, ext) && input->GetNumberOfPoints() > 0)
  {
    output->Crop(ext);
  }
  if (input->GetNumberOfPoints() == 0 || output->GetNumberOfPoints() == 0)
  {
    return 1;
  }
  output->GetExtent(ext);
  std::vector<double> values;
  int nc = 0, association = -1;
  vtkDataArray* array = this->GetInputArrayToProcess(DATA_ARRAY, input, association);
  if (!ReadData(this, array, association, input, 6, values, nc))
  {
    return 0;
  }
  const vtkBeltramiGraphFlow::ImageGrid grid = vtkBeltramiGraphFlow::GridOf(input, whole, inExt);
  beltrami::GraphOperatorOptions o;
  this->CopySettings(o, vtkBeltramiCopy::ToCore);
  Maps maps;
  const beltrami::GraphOperatorOutputs out =
    maps.Allocate(this, input->GetNumberOfPoints(), grid.Volume ? 3 : 2, nc, !grid.Volume);
  const beltrami::GraphOperatorReport r = grid.Volume
    ? beltrami::ComputeVolumeGraphOperators(grid.Voxels, nc, values.data(), o, out)
    : beltrami::ComputeImageGraphOperators(grid.Pixels, nc, values.data(), o, out);
  if (!r.Error.empty())
  {
    vtkErrorMacro(<< r.Error << ". The output is the input.");
    return 0;
  }
  // Output point o (the output extent) is input point ExtentIndex(inExt, ijk).
  const vtkIdType nx = ext[1] - ext[0] + 1, ny = ext[3] - ext[2] + 1;
  const auto source = [&](vtkIdType o) {
    const int ijk[3] = { static_cast<int>(ext[0] + o % nx), static_cast<int>(ext[2] + (o / nx) % ny),
      static_cast<int>(ext[4] + o / (nx * ny)) };
    return vtkBeltramiGraphFlow::ExtentIndex(inExt, ijk);
  };
  const int axes[3] = { grid.Volume ? 0 : grid.Axis0, grid.Volume ? 1 : grid.Axis1, 2 };
  WarnNonFiniteOperators(this, maps.AddTo(output, source, axes) + r.OverflowVertices);
  AddReport(output->GetFieldData(), r);
  return 1;
}

void vtkBeltramiOperators::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ContrastScale: " << this->ContrastScale << "\n";
  os << indent << "NoiseLevel: " << this->NoiseLevel << "\n";
  os << indent << "BoundaryHandling: " << this->BoundaryHandling << "\n";
  os << indent << "ComputeMeanCurvatureNormal: " << this->ComputeMeanCurvatureNormal << "\n";
  os << indent << "ComputeBeltramiOperator: " << this->ComputeBeltramiOperator << "\n";
  os << indent << "ComputeMeanCurvature: " << this->ComputeMeanCurvature << "\n";
  os << indent << "ComputeGaussianCurvature: " << this->ComputeGaussianCurvature << "\n";
  os << indent << "ComputeEdgeIndicator: " << this->ComputeEdgeIndicator << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
