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
  // The flow couples all points (semi-implicit steps, noise-level stop,
  // mean edge length): data split over the ranks of a distributed run are
  // smoothed whole on rank 0 (vtkBeltramiGather), as in a serial run.
  const auto smooth = [this](vtkBeltramiSurface& surface) -> bool {
    vtkPolyData* input = surface.Input();
    vtkPolyData* output = surface.Output();
    const beltrami::MeshTopology& topo = surface.Topology();
    int association = -1;
    vtkDataArray* array = this->GetInputArrayToProcess(SMOOTHED_ARRAY, input, association);
    if (!vtkBeltramiGraphFlow::IsPointArray(this, array, association))
    {
      return false;
    }
    if (topo.NumberOfTriangles() == 0)
    {
      vtkWarningMacro("Input has no polygons or triangle strips: the data are left as they are.");
      return true;
    }
    surface.WarnAboutInput(this, "a free boundary where pieces meet", "The data at non-manifold points are kept.");
    std::vector<double> storage;
    const double* points = surface.PointsAsDouble(storage);
    return vtkBeltramiGraphFlow::RunOnMesh(this, input, output, array, points, this->UseFixedPointsArray,
      vtkBeltramiGraphFlow::Options(this), 5, false,
      [&topo](const double* x, int nc, double* values, const std::uint8_t* fixed,
        const beltrami::GraphFlowOptions& options, const beltrami::ProgressCallback& progress) {
        return beltrami::RunSurfaceGraphFlow(topo, x, nc, values, fixed, options, progress);
      }) != 0;
  };
  return vtkBeltramiSurface::Execute(this, inputVector, outputVector, this->NumberOfThreads,
    vtkBeltramiSurface::Needs::WholeSurface, smooth);
}

void vtkSurfaceDataDenoising::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  vtkBeltramiGraphFlow::PrintSettings(this, os, indent);
  os << indent << "Units: " << this->Units << "\n";
}
