#include "vtkTetrahedralBeltramiDenoising.h"
#include "vtkBeltramiSettings.h"

#include "vtkBeltramiGather.h"
#include "vtkBeltramiGraphFlow.h"
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

#include <limits>
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
  // The flow couples all points (semi-implicit steps, noise-level stop,
  // mean edge length): data split over the ranks are smoothed whole on
  // rank 0, as in a serial run, and every rank gets its points' values.
  return vtkBeltramiGather::RunWhole(outputVector->GetInformationObject(0), input, output,
    vtkBeltramiGather::Results::ToEveryPiece, [this](vtkPointSet* in, vtkPointSet* out, int holding) {
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
  if (numPoints >= std::numeric_limits<beltrami::Index>::max())
  {
    vtkErrorMacro("Too many points (" << numPoints << "). The output is the input.");
    return 0;
  }
  if (holding > 1) // pieces streamed one by one: no gathering
  {
    vtkBeltramiSurface::WarnDistributed(this, holding, "a free boundary where pieces meet");
  }
  int association = -1;
  vtkDataArray* array = this->GetInputArrayToProcess(SMOOTHED_ARRAY, input, association);
  if (!vtkBeltramiGraphFlow::IsPointArray(this, array, association))
  {
    return 0;
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
  if (mesh.NumberOfDroppedTetrahedra() > 0)
  {
    vtkWarningMacro(<< mesh.NumberOfDroppedTetrahedra()
                    << " tetrahedra with repeated or invalid point ids are ignored.");
  }
  std::vector<double> points(3 * static_cast<std::size_t>(numPoints));
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    input->GetPoint(i, &points[3 * i]);
  }
  return vtkBeltramiGraphFlow::RunOnMesh(this, input, output, array, points.data(),
    this->UseFixedPointsArray, vtkBeltramiGraphFlow::Options(this), 6, this->LogEuclideanTensors,
    [&](const double* x, int nc, double* values, const std::uint8_t* fixed,
      const beltrami::GraphFlowOptions& options, const beltrami::ProgressCallback& progress) {
      return beltrami::RunTetrahedralGraphFlow(
        mesh, x, nc, values, fixed, options, progress, voxelsOnly ? &voxels : nullptr);
    });
}

void vtkTetrahedralBeltramiDenoising::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  vtkBeltramiGraphFlow::PrintSettings(this, os, indent);
  os << indent << "Units: " << this->Units << "\n";
  os << indent << "LogEuclideanTensors: " << this->LogEuclideanTensors << "\n";
}
