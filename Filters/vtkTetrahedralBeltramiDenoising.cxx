#include "vtkTetrahedralBeltramiDenoising.h"

#include "vtkBeltramiGraphFlow.h"

#include "Core/GraphFlow.h"
#include "Core/Tetrahedra.h"

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <limits>
#include <vector>

vtkStandardNewMacro(vtkTetrahedralBeltramiDenoising);

vtkTetrahedralBeltramiDenoising::vtkTetrahedralBeltramiDenoising()
{
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

int vtkTetrahedralBeltramiDenoising::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0]);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
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
  int association = -1;
  vtkDataArray* array = this->GetInputArrayToProcess(0, inputVector, association);
  if (!vtkBeltramiGraphFlow::IsPointArray(this, array, association))
  {
    return 0;
  }

  // The tetrahedra; other cells are ignored.
  std::vector<beltrami::Index> tets;
  vtkIdType others = 0;
  vtkCellArray* cells = input->GetCells();
  vtkUnsignedCharArray* types = input->GetCellTypesArray();
  if (cells && types)
  {
    auto it = vtk::TakeSmartPointer(cells->NewIterator());
    vtkIdType cellId = 0;
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cellId)
    {
      vtkIdType n = 0;
      const vtkIdType* ids = nullptr;
      it->GetCurrentCell(n, ids);
      if (types->GetValue(cellId) != VTK_TETRA || n != 4)
      {
        ++others;
        continue;
      }
      for (int a = 0; a < 4; ++a)
      {
        tets.push_back(static_cast<beltrami::Index>(ids[a]));
      }
    }
  }
  if (others > 0)
  {
    vtkWarningMacro(<< others << " cells that are not tetrahedra are ignored "
                    << "(tetrahedralize them first, e.g. with vtkDataSetTriangleFilter).");
  }
  if (tets.empty())
  {
    vtkWarningMacro("The input has no tetrahedra: the data are left as they are.");
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
  const double unit = this->Units == MEAN_EDGE_LENGTH ? mesh.MeanEdgeLength(points.data()) : 1.0;
  return vtkBeltramiGraphFlow::RunOnMesh(this, input, output, array, points.data(),
    this->UseFixedPointsArray, vtkBeltramiGraphFlow::Options(this), 6, unit, 3,
    [&mesh](const double* x, int nc, double* values, const std::uint8_t* fixed,
      const beltrami::GraphFlowOptions& options, const beltrami::ProgressCallback& progress) {
      return beltrami::RunTetrahedralGraphFlow(mesh, x, nc, values, fixed, options, progress);
    });
}

void vtkTetrahedralBeltramiDenoising::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  vtkBeltramiGraphFlow::PrintSettings(this, os, indent);
  os << indent << "Units: " << this->Units << "\n";
  os << indent << "UseFixedPointsArray: " << this->UseFixedPointsArray << "\n";
}
