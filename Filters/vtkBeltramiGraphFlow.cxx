#include "vtkBeltramiGraphFlow.h"

#include "vtkBeltramiPieces.h"
#include "vtkBeltramiSurface.h"

#include "Flows/TensorSpace.h"

#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkPointData.h>

#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>

#include <vtkAlgorithm.h>
#include <vtkSmartPointer.h>

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellType.h>
#include <vtkExtentTranslator.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationIntegerRequestKey.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include "Mesh/Tetrahedra.h"

#include <algorithm>
#include <cmath>
#include <sstream>

bool vtkBeltramiGraphFlow::IsPointArray(vtkAlgorithm* owner, vtkDataArray* array, int association)
{
  if (!array || association != vtkDataObject::FIELD_ASSOCIATION_POINTS)
  {
    vtkErrorWithObjectMacro(owner, "No point array to smooth: select a point data array (input array 0). "
                                   "The output is the input.");
    return false;
  }
  return true;
}

void vtkBeltramiGraphFlow::ReplaceArray(
  vtkDataSet* input, vtkDataSet* output, vtkDataArray* original, vtkDataArray* smoothed)
{
  vtkPointData* pd = output->GetPointData();
  pd->AddArray(smoothed);
  if (input->GetPointData()->GetScalars() == original)
  {
    pd->SetScalars(smoothed);
  }
}

vtkSmartPointer<vtkDataArray> vtkBeltramiGraphFlow::ArrayLike(
  vtkDataArray* like, const double* values, vtkIdType tuples)
{
  const int nc = like->GetNumberOfComponents();
  vtkSmartPointer<vtkDataArray> out = vtkBeltramiSurface::NewArray(like->GetDataType(), like->GetName(), nc, tuples);
  const vtkIdType count = tuples * nc;
  switch (out->GetDataType())
  {
    vtkTemplateMacro(std::transform(values, values + count, static_cast<VTK_TT*>(out->GetVoidPointer(0)),
      [](double v) { return ToValue<VTK_TT>(v); }));
    default: // (no other types: the flows read numeric arrays)
      for (vtkIdType j = 0; j < count; ++j)
      {
        out->SetComponent(j / nc, static_cast<int>(j % nc), values[j]);
      }
  }
  return out;
}

void vtkBeltramiGraphFlow::AddReport(vtkFieldData* fd, const beltrami::GraphFlowResult& r)
{
  const auto addInt = [fd](const char* name, int value) {
    vtkNew<vtkIntArray> a;
    a->SetName(name);
    a->InsertNextValue(value);
    fd->AddArray(a);
  };
  const auto addDouble = [fd](const char* name, std::initializer_list<double> values) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name);
    for (double v : values)
    {
      a->InsertNextValue(v);
    }
    fd->AddArray(a);
  };
  addInt("FlowIterations", r.Iterations);
  addDouble("FlowTime", { r.Time });
  addDouble("FlowRMSChange", { r.RMSChange });
  addDouble("FlowArea", { r.InitialArea, r.FinalArea });
  addInt("FlowSolverIterations", r.SolverIterations);
  addDouble("EstimatedNoiseLevel", { r.EstimatedNoiseLevel });
  addDouble("FlowNoiseLevel", { r.NoiseLevel });
  addDouble("FlowContrastScale", { r.ContrastScale });
  if (r.InitialRisk > 0.0)
  {
    addDouble("FlowEstimatedError", { r.InitialRisk, r.FinalRisk });
  }
}

std::string vtkBeltramiGraphFlow::RunWarnings(
  const beltrami::GraphFlowOptions& o, const beltrami::GraphFlowResult& r)
{
  std::ostringstream s;
  if (r.StoppedByLimit)
  {
    s << "The flow reached its iteration limit ("
      << (o.Stop == beltrami::GraphFlowStop::Iterations ? o.NumberOfIterations : o.MaximumNumberOfIterations)
      << ") before its stopping rule"
      << (o.Stop == beltrami::GraphFlowStop::Iterations ? " (the noise level)" : "")
      << ": the data may be under-smoothed. Raise "
      << (o.Stop == beltrami::GraphFlowStop::Iterations ? "NumberOfIterations" : "MaximumNumberOfIterations")
      << " or use a larger TimeStep.";
  }
  if (!r.SolverConverged)
  {
    s << (s.tellp() > 0 ? " " : "") << "The linear solver of the semi-implicit steps stopped short of its "
      << "tolerance (relative residual " << r.LargestSolverResidual
      << "): the result is approximate; a smaller TimeStep gives better-conditioned steps.";
  }
  if (r.UnstableSteps == 0)
  {
    return s.str();
  }
  s << (s.tellp() > 0 ? " " : "");
  s << r.UnstableSteps << " explicit step(s) of " << (o.TimeStep > 0.0 ? o.TimeStep : r.LastTimeStep)
    << " exceeded the stability limit (" << r.SmallestStableStep
    << " at the steepest point); the result may oscillate. Use AdaptiveTimeStep, the semi-implicit "
       "integration or a smaller TimeStep.";
  return s.str();
}

void vtkBeltramiGraphFlow::ToLogEuclidean(vtkAlgorithm* owner, const char* name, double* values, vtkIdType count,
  int numThreads, beltrami::GraphFlowOptions& options, const beltrami::Partition* split)
{
  const std::int64_t raised = beltrami::SymmetricTensorsToLog(values, count, 6, 1e-6, numThreads, split);
  if (raised && (!split || split->Rank() == 0)) // (a split run's count is global)
  {
    vtkWarningWithObjectMacro(owner, << raised << " tensors of '" << name << "' are not positive definite (or "
      "have eigenvalues below 1e-6 of the field's largest): those eigenvalues were raised to that floor.");
  }
  options.ToNoiseSpace = [count, numThreads](double* x) { beltrami::LogToSymmetricTensors(x, count, 6, numThreads); };
  options.FromNoiseSpace = [count, numThreads, split](double* x) {
    beltrami::SymmetricTensorsToLog(x, count, 6, 1e-6, numThreads, split);
  };
}

bool vtkBeltramiGraphFlow::ReadMeshInput(vtkAlgorithm* owner, vtkDataSet* input, vtkDataArray* array,
  bool useMask, int maxComponents, bool logEuclidean, std::vector<double>& values, std::vector<std::uint8_t>& fixed)
{
  std::string error;
  fixed = useMask ? vtkBeltramiSurface::SelectedPointMask(owner, input, 1, "fixed-points", error)
                  : std::vector<std::uint8_t>();
  if (!error.empty())
  {
    vtkErrorWithObjectMacro(owner, << error << " The output is the input.");
    return false;
  }
  const int nc = array->GetNumberOfComponents();
  if (nc < 1 || nc > maxComponents)
  {
    vtkErrorWithObjectMacro(owner, "The array '" << (array->GetName() ? array->GetName() : "") << "' has "
                                                 << nc << " components; 1 to " << maxComponents
                                                 << " can be smoothed. The output is the input.");
    return false;
  }
  if (logEuclidean && nc != 6)
  {
    vtkErrorWithObjectMacro(owner, "Log-Euclidean smoothing needs symmetric tensors of 6 components (XX, YY, ZZ, "
      "XY, YZ, XZ); '" << (array->GetName() ? array->GetName() : "") << "' has " << nc
      << ". The output is the input.");
    return false;
  }
  const vtkIdType numPoints = input->GetNumberOfPoints();
  values.resize(static_cast<std::size_t>(numPoints) * nc);
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    for (int k = 0; k < nc; ++k)
    {
      values[i * nc + k] = array->GetComponent(i, k);
    }
  }
  return true;
}

int vtkBeltramiGraphFlow::RunOnMesh(vtkAlgorithm* owner, vtkDataSet* input, vtkDataSet* output,
  vtkDataArray* array, const double* points, bool useMask, const beltrami::GraphFlowOptions& meshOptions,
  int maxComponents, bool logEuclidean, const MeshFlow& flow, const vtkBeltramiPieces* split)
{
  std::vector<double> values;
  std::vector<std::uint8_t> fixed;
  const bool empty = split && split->Split() && input->GetNumberOfPoints() == 0; // (it may lack the arrays)
  const bool ok = empty || ReadMeshInput(owner, input, array, useMask, maxComponents, logEuclidean, values, fixed);
  if (split ? !split->AllAgree(ok) : !ok)
  {
    return 0;
  }
  int nc = empty ? 0 : array->GetNumberOfComponents();
  if (const beltrami::Partition* rows = split ? split->Split() : nullptr)
  {
    // One value per point of the topology: the ghost points' from their owners.
    nc = static_cast<int>(rows->Max(nc));
    values.resize(static_cast<std::size_t>(rows->Rows()) * nc);
    rows->UpdateGhosts(values.data(), nc);
    if (rows->Max(fixed.empty() ? 0.0 : 1.0) > 0.0)
    {
      fixed.resize(rows->Rows(), 0);
      rows->UpdateGhosts(fixed);
    }
  }
  const vtkIdType numPoints = input->GetNumberOfPoints();
  beltrami::GraphFlowOptions options = meshOptions;
  std::vector<double> logInput; // log-Euclidean: the input's log coordinates
  if (logEuclidean) // (every row of a split piece: its ghost rows too)
  {
    ToLogEuclidean(owner, empty ? "" : array->GetName() ? array->GetName() : "", values.data(),
      static_cast<vtkIdType>(values.size() / 6), options.NumberOfThreads, options, split ? split->Split() : nullptr);
    logInput.assign(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(numPoints) * nc);
  }
  owner->UpdateProgress(0.0);
  const beltrami::GraphFlowResult result = flow(points, nc, values.data(),
    fixed.empty() ? nullptr : fixed.data(), options, [owner](double fraction) {
      owner->UpdateProgress(fraction);
      return !owner->GetAbortExecute();
    });
  if (!result.Error.empty())
  {
    vtkErrorWithObjectMacro(owner, << result.Error << ". The output is the input.");
    return 0;
  }
  if (!result.Completed || empty)
  {
    return 1;
  }
  const std::string warning = RunWarnings(options, result);
  if (!warning.empty())
  {
    vtkWarningWithObjectMacro(owner, << warning);
  }
  if (logEuclidean)
  {
    // The tensors the flow kept (fixed points, points in no cell): exactly
    // the input's, not through the round trip of log and exp.
    std::vector<std::uint8_t> kept(static_cast<std::size_t>(numPoints));
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      kept[i] = std::equal(logInput.begin() + 6 * i, logInput.begin() + 6 * (i + 1), values.begin() + 6 * i);
    }
    beltrami::LogToSymmetricTensors(values.data(), numPoints, 6, options.NumberOfThreads);
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      for (int k = 0; kept[i] && k < 6; ++k)
      {
        values[6 * i + k] = array->GetComponent(i, k);
      }
    }
  }
  ReplaceArray(input, output, array, ArrayLike(array, values.data(), numPoints));
  AddReport(output->GetFieldData(), result);
  if (split && split->Split())
  {
    split->AddDistribution(output->GetFieldData(), "FlowDistribution");
  }
  return 1;
}

vtkBeltramiGraphFlow::ImageGrid vtkBeltramiGraphFlow::GridOf(vtkImageData* image, const int* whole, const int* ext)
{
  ImageGrid grid;
  int axes[3], nAxes = 0;
  for (int a = 0; a < 3; ++a)
  {
    if (whole[2 * a + 1] > whole[2 * a])
    {
      axes[nAxes++] = a;
    }
  }
  grid.Volume = nAxes == 3;
  for (int a = 0; a < 3 && nAxes < 2; ++a)
  {
    if (nAxes == 0 || axes[0] != a)
    {
      axes[nAxes++] = a;
    }
  }
  const double* spacing = image->GetSpacing();
  const auto size = [ext](int a) { return std::max(0, ext[2 * a + 1] - ext[2 * a] + 1); };
  if (grid.Volume)
  {
    grid.Voxels.Width = size(0);
    grid.Voxels.Height = size(1);
    grid.Voxels.Depth = size(2);
    grid.Voxels.SpacingX = std::abs(spacing[0]);
    grid.Voxels.SpacingY = std::abs(spacing[1]);
    grid.Voxels.SpacingZ = std::abs(spacing[2]);
    return grid;
  }
  grid.Axis0 = std::min(axes[0], axes[1]);
  grid.Axis1 = std::max(axes[0], axes[1]);
  grid.Pixels.Width = size(grid.Axis0);
  grid.Pixels.Height = size(grid.Axis1);
  grid.Pixels.SpacingX = std::abs(spacing[grid.Axis0]);
  grid.Pixels.SpacingY = std::abs(spacing[grid.Axis1]);
  return grid;
}

vtkIdType vtkBeltramiGraphFlow::ExtentIndex(const int* e, const int* ijk)
{
  const vtkIdType nx = e[1] - e[0] + 1, ny = e[3] - e[2] + 1;
  return (ijk[0] - e[0]) + nx * ((ijk[1] - e[2]) + ny * static_cast<vtkIdType>(ijk[2] - e[4]));
}

void vtkBeltramiGraphFlow::RequestImageExtent(vtkInformation* inInfo, vtkInformation* outInfo, int rings)
{
  int whole[6], ext[6];
  inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), ext);
  const int pieces = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    : 1;
  if (pieces > 1)
  {
    // The executive will split our update extent into this piece just before
    // RequestData (CAN_PRODUCE_SUB_EXTENT): make the same split here, and ask
    // the input for the extent this piece needs as one piece of its own, or
    // the input's executive would split it again (without our ghost rings).
    const int piece = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER());
    const int ghosts = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS());
    vtkInformationIntegerKey* splitKey = vtkExtentTranslator::UPDATE_SPLIT_MODE();
    const int mode = outInfo->Has(splitKey) ? outInfo->Get(splitKey) : vtkExtentTranslator::BLOCK_MODE;
    vtkNew<vtkExtentTranslator> translator;
    int pieceExt[6];
    if (!translator->PieceToExtentThreadSafe(piece, pieces, ghosts, ext, pieceExt, mode, 0))
    {
      pieceExt[0] = pieceExt[2] = pieceExt[4] = 0; // an empty piece
      pieceExt[1] = pieceExt[3] = pieceExt[5] = -1;
    }
    std::copy(pieceExt, pieceExt + 6, ext);
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  }
  for (int a = 0; a < 3; ++a)
  {
    if (rings < 0)
    {
      ext[2 * a] = whole[2 * a];
      ext[2 * a + 1] = whole[2 * a + 1];
    }
    else if (ext[2 * a] <= ext[2 * a + 1])
    {
      ext[2 * a] = std::max(whole[2 * a], ext[2 * a] - rings);
      ext[2 * a + 1] = std::min(whole[2 * a + 1], ext[2 * a + 1] + rings);
    }
  }
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), ext, 6);
}

std::vector<beltrami::Index> vtkBeltramiGraphFlow::Tetrahedra(
  vtkAlgorithm* owner, vtkUnstructuredGrid* input, std::vector<beltrami::Index>* voxels)
{
  // The tetrahedra, and voxels (VTK_VOXEL, e.g. the active voxels of a
  // sparse OpenVDB grid) split into their six Kuhn tetrahedra (as the 3D
  // image path: conforming, since all voxels share the axes); other cells
  // are ignored.
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
      const int type = types->GetValue(cellId);
      if (type == VTK_TETRA && n == 4)
      {
        for (int a = 0; a < 4; ++a)
        {
          tets.push_back(static_cast<beltrami::Index>(ids[a]));
        }
      }
      else if (type == VTK_VOXEL && n == 8)
      {
        if (voxels)
        {
          voxels->insert(voxels->end(), ids, ids + 8);
        }
        // VTK_VOXEL numbers its corners x + 2y + 4z, the corner bits of KuhnPaths.
        for (const auto& path : beltrami::KuhnPaths)
        {
          const int first = 1 << path[0], second = first | (1 << path[1]);
          for (const int corner : { 0, first, second, 7 })
          {
            tets.push_back(static_cast<beltrami::Index>(ids[corner]));
          }
        }
      }
      else
      {
        ++others;
      }
    }
  }
  if (others > 0)
  {
    vtkWarningWithObjectMacro(owner, << others << " cells that are neither tetrahedra nor voxels are ignored "
                    << "(tetrahedralize them first, e.g. with vtkDataSetTriangleFilter).");
  }
  return tets;
}

std::vector<double> vtkBeltramiGraphFlow::PointsOf(vtkDataSet* input)
{
  const vtkIdType numPoints = input->GetNumberOfPoints();
  std::vector<double> points(3 * static_cast<std::size_t>(numPoints));
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    input->GetPoint(i, &points[3 * i]);
  }
  return points;
}

void vtkBeltramiGraphFlow::WarnDropped(vtkAlgorithm* owner, const beltrami::TetrahedralMesh& mesh)
{
  if (mesh.NumberOfDroppedTetrahedra() > 0)
  {
    vtkWarningWithObjectMacro(owner, << mesh.NumberOfDroppedTetrahedra()
                                     << " tetrahedra with repeated or invalid point ids are ignored.");
  }
}

bool vtkBeltramiGraphFlow::SplitTetrahedra(vtkAlgorithm* owner, vtkUnstructuredGrid* input,
  vtkBeltramiPieces& pieces, bool allStars, int numberOfThreads, SplitMesh& split)
{
  // The piece, and its edge: its points on faces of one tetrahedron.
  const beltrami::Index n = static_cast<beltrami::Index>(input->GetNumberOfPoints());
  std::vector<beltrami::Index> tets = n > 0 ? Tetrahedra(owner, input) : std::vector<beltrami::Index>();
  // Copies within the piece (two of RedistributeDataSet's regions on one rank): one is kept.
  std::vector<std::uint8_t> repeated(tets.size() / 4, 0);
  vtkBeltramiPieces::RepeatedCells(4, tets, repeated);
  std::vector<beltrami::Index> unique;
  for (std::size_t t = 0; t < repeated.size(); ++t)
  {
    if (!repeated[t])
    {
      unique.insert(unique.end(), tets.begin() + 4 * t, tets.begin() + 4 * t + 4);
    }
  }
  std::vector<std::uint8_t> edge;
  {
    const beltrami::TetrahedralMesh piece(n, std::move(unique), numberOfThreads);
    WarnDropped(owner, piece);
    edge = piece.BoundaryVertices();
    for (beltrami::Index v = 0; v < n; ++v)
    {
      edge[v] = edge[v] && piece.IncidentBegin(v) != piece.IncidentEnd(v); // (not points in no tetrahedron)
    }
    tets = piece.TetrahedronList();
    split.OwnTetrahedra = piece.NumberOfTetrahedra();
  }
  std::vector<double>& points = split.Points;
  points = PointsOf(input);
  const auto at = [&points](beltrami::Index i, double* x) { std::copy_n(&points[3 * static_cast<std::size_t>(i)], 3, x); };
  pieces.ShareCopiedCells(4, n, at, tets, edge); // tetrahedra other pieces hold too (collective)
  pieces.AddRings(4, n, at, edge, tets, allStars ? vtkBeltramiPieces::Stars::All : vtkBeltramiPieces::Stars::Owned);
  points.insert(points.end(), pieces.GhostPoints().begin(), pieces.GhostPoints().end());
  const beltrami::Index rows = static_cast<beltrami::Index>(points.size() / 3);
  split.Mesh = std::make_unique<beltrami::TetrahedralMesh>(rows, std::move(tets), numberOfThreads);
  std::string error;
  if (!pieces.AllAgree(pieces.BuildPartition(rows, n, at, error)))
  {
    vtkErrorWithObjectMacro(owner, "Cannot split the solve over the ranks: "
        << (error.empty() ? "another rank failed (see its error)" : error) << ". The output is the input.");
    return false;
  }
  return true;
}
