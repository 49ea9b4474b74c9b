#include "vtkSurfaceDataDenoising.h"
#include "vtkBeltramiSettings.h"

#include "vtkBeltramiGraphFlow.h"
#include "vtkBeltramiSurface.h"

#include "Flows/GraphFlow.h"

#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

#include <cmath>
#include <vector>

BELTRAMI_SAME_ENUM(vtkSurfaceDataDenoising::EXPLICIT, beltrami::GraphFlowIntegration::Explicit);
BELTRAMI_SAME_ENUM(vtkSurfaceDataDenoising::SEMI_IMPLICIT, beltrami::GraphFlowIntegration::SemiImplicit);

vtkStandardNewMacro(vtkSurfaceDataDenoising);

BELTRAMI_SAME_ENUM(vtkSurfaceDataDenoising::MEAN_EDGE_LENGTH, beltrami::LengthUnit::MeanEdgeLength);
BELTRAMI_SAME_ENUM(vtkSurfaceDataDenoising::PHYSICAL, beltrami::LengthUnit::Physical);

vtkSurfaceDataDenoising::vtkSurfaceDataDenoising()
{
  beltrami::GraphFlowOptions defaults = beltrami::GraphFlowOptions::ForMeshes();
  vtkBeltramiGraphFlow::CopySettings(this, defaults, vtkBeltramiCopy::FromCore);
  this->SetInputArrayToProcess(
    SMOOTHED_ARRAY, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

int vtkSurfaceDataDenoising::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The flow couples all points (the semi-implicit solves, the stops' sums,
  // the noise estimate, the mean edge length): data split over the ranks of
  // a distributed run are smoothed over the ranks, each rank its piece and
  // the rings around it (pieces with ghost cells are gathered on rank 0).
  const auto smooth = [this](vtkBeltramiSurface& surface) -> bool {
    vtkPolyData* input = surface.Input();
    const beltrami::MeshTopology& topo = surface.Topology();
    const beltrami::Partition* split = surface.Split(); // every rank runs, an empty piece's too
    int association = -1;
    vtkDataArray* array = this->GetInputArrayToProcess(SMOOTHED_ARRAY, input, association);
    const bool empty = split && input->GetNumberOfPoints() == 0;
    if (!surface.AllAgree(empty || vtkBeltramiGraphFlow::IsPointArray(this, array, association)))
    {
      return false;
    }
    const double triangles = static_cast<double>(topo.NumberOfTriangles());
    if ((split ? split->Sum(triangles) : triangles) == 0.0)
    {
      vtkWarningMacro("Input has no polygons or triangle strips: the data are left as they are.");
      return true;
    }
    if (!split) // (a split piece's own defects are those of its cut)
    {
      surface.WarnAboutInput(this, "a free boundary where pieces meet", "The data at non-manifold points are kept.");
    }
    std::vector<double> storage;
    const double* points = surface.PointsAsDouble(storage);
    return vtkBeltramiGraphFlow::RunOnMesh(this, input, surface.Output(), array, points, this->UseFixedPointsArray,
      vtkBeltramiGraphFlow::Options(this), 5, false,
      [&topo, split](const double* x, int nc, double* values, const std::uint8_t* fixed,
        const beltrami::GraphFlowOptions& options, const beltrami::ProgressCallback& progress) {
        return beltrami::RunSurfaceGraphFlow(topo, x, nc, values, fixed, options, progress, split);
      },
      &surface.SplitPieces()) != 0;
  };
  return vtkBeltramiSurface::Execute(this, inputVector, outputVector, this->NumberOfThreads,
    vtkBeltramiSurface::Needs::Distributed, smooth);
}

void vtkSurfaceDataDenoising::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  vtkBeltramiGraphFlow::PrintSettings(this, os, indent);
  os << indent << "Units: " << this->Units << "\n";
}
