#include "vtkSurfaceDataDenoising.h"

#include "vtkBeltramiGraphFlow.h"
#include "vtkBeltramiSurface.h"

#include "Core/Fairing.h"
#include "Core/GraphFlow.h"

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

vtkStandardNewMacro(vtkSurfaceDataDenoising);

vtkSurfaceDataDenoising::vtkSurfaceDataDenoising()
{
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

int vtkSurfaceDataDenoising::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkBeltramiSurface surface;
  const auto prepared = surface.Prepare(this, inputVector, outputVector, this->NumberOfThreads);
  if (prepared != vtkBeltramiSurface::Ready)
  {
    return prepared == vtkBeltramiSurface::NothingToDo;
  }
  vtkPolyData* input = surface.Input();
  vtkPolyData* output = surface.Output();
  const beltrami::MeshTopology& topo = surface.Topology();
  const vtkIdType numPoints = input->GetNumberOfPoints();

  int association = -1;
  vtkDataArray* array = this->GetInputArrayToProcess(0, inputVector, association);
  if (!array || association != vtkDataObject::FIELD_ASSOCIATION_POINTS)
  {
    vtkErrorMacro("No point array to smooth: select a point data array (input array 0). "
                  "The output is the input.");
    return 0;
  }
  std::string error;
  const std::vector<std::uint8_t> fixed =
    this->UseFixedPointsArray ? vtkBeltramiGraphFlow::FixedMask(this, input, array, "fixed-points", error)
                              : std::vector<std::uint8_t>();
  if (!error.empty())
  {
    vtkErrorMacro(<< error << " The output is the input.");
    return 0;
  }
  const int nc = array->GetNumberOfComponents();
  if (nc < 1 || nc > 5)
  {
    vtkErrorMacro("The array '" << (array->GetName() ? array->GetName() : "") << "' has " << nc
                                << " components; 1 to 5 can be smoothed. The output is the input.");
    return 0;
  }
  if (topo.NumberOfTriangles() == 0)
  {
    vtkWarningMacro("Input has no polygons or triangle strips: the data are left as they are.");
    return 1;
  }
  if (surface.NumberOfPieces() <= 1 && !surface.TopologyWarning().empty())
  {
    vtkWarningMacro(<< surface.TopologyWarning() << ". The data at non-manifold points are kept.");
  }

  std::vector<double> storage;
  const double* points = surface.PointsAsDouble(storage);
  std::vector<double> scaled;
  double h = 1.0;
  if (this->Units == MEAN_EDGE_LENGTH)
  {
    h = beltrami::MeanEdgeLength(topo, points);
    if (!(h > 0.0) || !std::isfinite(h))
    {
      vtkErrorMacro("The mean edge length of the input is " << h << ": cannot scale the mesh. "
                                                            << "The output is the input.");
      return 0;
    }
    scaled.assign(points, points + 3 * numPoints);
    for (double& x : scaled)
    {
      x /= h;
    }
    points = scaled.data();
  }
  for (vtkIdType k = 0; k < 3 * numPoints; ++k)
  {
    if (!std::isfinite(points[k]))
    {
      vtkErrorMacro("The input has NaN or infinite point coordinates. The output is the input.");
      return 0;
    }
  }

  std::vector<double> values(static_cast<std::size_t>(numPoints) * nc);
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    for (int k = 0; k < nc; ++k)
    {
      values[i * nc + k] = array->GetComponent(i, k);
    }
  }

  const beltrami::GraphFlowOptions options = vtkBeltramiGraphFlow::Options(this);
  this->UpdateProgress(0.0);
  beltrami::GraphFlowResult result = beltrami::RunSurfaceGraphFlow(topo, points, nc, values.data(),
    fixed.empty() ? nullptr : fixed.data(), options, [this](double fraction) {
      this->UpdateProgress(fraction);
      return !this->GetAbortExecute();
    });
  if (!result.Error.empty())
  {
    vtkErrorMacro(<< result.Error << ". The output is the input.");
    return 0;
  }
  if (result.Cancelled)
  {
    return 1;
  }
  const std::string warning = vtkBeltramiGraphFlow::StabilityWarning(options, result);
  if (!warning.empty())
  {
    vtkWarningMacro(<< warning);
  }
  vtkNew<vtkDoubleArray> smoothed;
  smoothed->SetName(array->GetName());
  smoothed->SetNumberOfComponents(nc);
  smoothed->SetNumberOfTuples(numPoints);
  std::copy(values.begin(), values.end(), smoothed->GetPointer(0));
  vtkBeltramiGraphFlow::ReplaceArray(input, output, array, smoothed);
  // Areas in the units the flow used: report them in the mesh's units.
  result.InitialArea *= h * h;
  result.FinalArea *= h * h;
  result.Time *= h * h;
  vtkBeltramiGraphFlow::AddReport(output->GetFieldData(), result);
  return 1;
}

void vtkSurfaceDataDenoising::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  vtkBeltramiGraphFlow::PrintSettings(this, os, indent);
  os << indent << "Units: " << this->Units << "\n";
}
