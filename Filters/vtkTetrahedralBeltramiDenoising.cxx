#include "vtkTetrahedralBeltramiDenoising.h"
#include "vtkBeltramiSettings.h"

#include "vtkBeltramiGather.h"
#include "vtkBeltramiGraphFlow.h"
#include "vtkBeltramiPieces.h"
#include "vtkBeltramiSurface.h"

#include "Flows/GraphFlow.h"
#include "Mesh/Tetrahedra.h"

#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

BELTRAMI_SAME_ENUM(vtkTetrahedralBeltramiDenoising::EXPLICIT, beltrami::GraphFlowIntegration::Explicit);
BELTRAMI_SAME_ENUM(vtkTetrahedralBeltramiDenoising::SEMI_IMPLICIT, beltrami::GraphFlowIntegration::SemiImplicit);

vtkStandardNewMacro(vtkTetrahedralBeltramiDenoising);

BELTRAMI_SAME_ENUM(vtkTetrahedralBeltramiDenoising::MEAN_EDGE_LENGTH, beltrami::LengthUnit::MeanEdgeLength);
BELTRAMI_SAME_ENUM(vtkTetrahedralBeltramiDenoising::PHYSICAL, beltrami::LengthUnit::Physical);

vtkTetrahedralBeltramiDenoising::vtkTetrahedralBeltramiDenoising()
{
  beltrami::GraphFlowOptions defaults = beltrami::GraphFlowOptions::ForMeshes();
  vtkBeltramiGraphFlow::CopySettings(this, defaults, vtkBeltramiCopy::FromCore);
  this->SetInputArrayToProcess(
    SMOOTHED_ARRAY, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

int vtkTetrahedralBeltramiDenoising::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0]);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  // The flow couples all points (semi-implicit steps, noise-level stop,
  // mean edge length).  Data split over ranks that can solve together
  // (pvbatch, pvserver; pieces without ghost cells) are smoothed over the
  // ranks, each rank its piece and the tetrahedra around it; pieces with
  // ghost cells are gathered and smoothed whole on rank 0, as in a serial
  // run, and every rank gets its points' values.
  // (Every rank takes the same branch: the counts are collective.)
  if (vtkBeltramiPieces::CanSolveTogether(outInfo) &&
    vtkBeltramiSurface::PiecesHoldingData(outInfo, input) > 1 && vtkBeltramiPieces::RingsAreMissing(input))
  {
    return this->SmoothSplit(input, output);
  }
  return vtkBeltramiGather::RunWhole(outInfo, input, output, vtkBeltramiGather::Results::ToEveryPiece,
    [this](vtkPointSet* in, vtkPointSet* out, int holding) {
      return this->Smooth(vtkUnstructuredGrid::SafeDownCast(in), vtkUnstructuredGrid::SafeDownCast(out), holding);
    });
}

int vtkTetrahedralBeltramiDenoising::Smooth(
  vtkUnstructuredGrid* input, vtkUnstructuredGrid* output, int holding)
{
  if (!input || !output)
  {
    vtkErrorMacro("Input and output must be vtkUnstructuredGrid.");
    return 0;
  }
  output->ShallowCopy(input); // a defined output: the input
  const vtkIdType numPoints = input->GetNumberOfPoints();
  if (numPoints == 0)
  {
    return 1;
  }
  if (!this->FitsIndex(numPoints))
  {
    return 0;
  }
  if (holding > 1) // pieces streamed one by one: no gathering
  {
    vtkBeltramiSurface::WarnDistributed(this, holding, "a free boundary where pieces meet");
  }
  std::vector<beltrami::Index> voxels;
  std::vector<beltrami::Index> tets = vtkBeltramiGraphFlow::Tetrahedra(this, input, &voxels);
  // Voxels alone (the active voxels of a sparse grid): the voxel-cell kernel.
  const bool voxelsOnly = !voxels.empty() && tets.size() == 3 * voxels.size();
  if (tets.empty())
  {
    vtkWarningMacro("The input has no tetrahedra or voxels: the data are left as they are.");
    return 1;
  }
  const beltrami::TetrahedralMesh mesh(static_cast<beltrami::Index>(numPoints), std::move(tets),
    this->NumberOfThreads);
  vtkBeltramiGraphFlow::WarnDropped(this, mesh);
  const std::vector<double> points = vtkBeltramiGraphFlow::PointsOf(input);
  return this->Run(input, output, points.data(), mesh, voxelsOnly ? &voxels : nullptr, nullptr);
}

int vtkTetrahedralBeltramiDenoising::SmoothSplit(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output)
{
  vtkNew<vtkUnstructuredGrid> none, discarded; // a missing input or output: an empty piece
  input = input ? input : none.Get();
  output = output ? output : discarded.Get();
  output->ShallowCopy(input); // a defined output: the input
  vtkBeltramiPieces pieces;
  pieces.SetCollective(true);
  if (!pieces.AllAgree(this->FitsIndex(input->GetNumberOfPoints())))
  {
    return 0;
  }
  vtkBeltramiGraphFlow::SplitMesh split;
  if (!vtkBeltramiGraphFlow::SplitTetrahedra(this, input, pieces, false, this->NumberOfThreads, split))
  {
    return 0;
  }
  const double own = split.OwnTetrahedra;
  if (pieces.Split()->Sum(own) == 0.0)
  {
    if (pieces.Split()->Rank() == 0)
    {
      vtkWarningMacro("The input has no tetrahedra or voxels: the data are left as they are.");
    }
    return 1;
  }
  return this->Run(input, output, split.Points.data(), *split.Mesh, nullptr, &pieces);
}

int vtkTetrahedralBeltramiDenoising::Run(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output,
  const double* points, const beltrami::TetrahedralMesh& mesh, const std::vector<beltrami::Index>* voxels,
  const vtkBeltramiPieces* pieces)
{
  int association = -1;
  vtkDataArray* array = this->GetInputArrayToProcess(SMOOTHED_ARRAY, input, association);
  const bool empty = pieces && input->GetNumberOfPoints() == 0; // (it may lack the arrays)
  const bool ok = empty || vtkBeltramiGraphFlow::IsPointArray(this, array, association);
  if (pieces ? !pieces->AllAgree(ok) : !ok)
  {
    return 0;
  }
  const beltrami::Partition* split = pieces ? pieces->Split() : nullptr;
  return vtkBeltramiGraphFlow::RunOnMesh(this, input, output, array, points, this->UseFixedPointsArray,
    vtkBeltramiGraphFlow::Options(this), 6, this->LogEuclideanTensors,
    [&](const double* x, int nc, double* values, const std::uint8_t* fixed,
      const beltrami::GraphFlowOptions& options, const beltrami::ProgressCallback& progress) {
      return beltrami::RunTetrahedralGraphFlow(mesh, x, nc, values, fixed, options, progress, voxels, split);
    },
    pieces);
}

bool vtkTetrahedralBeltramiDenoising::FitsIndex(vtkIdType numPoints)
{
  if (numPoints >= std::numeric_limits<beltrami::Index>::max())
  {
    vtkErrorMacro("Too many points (" << numPoints << "). The output is the input.");
    return false;
  }
  return true;
}

void vtkTetrahedralBeltramiDenoising::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  vtkBeltramiGraphFlow::PrintSettings(this, os, indent);
  os << indent << "Units: " << this->Units << "\n";
  os << indent << "LogEuclideanTensors: " << this->LogEuclideanTensors << "\n";
}
