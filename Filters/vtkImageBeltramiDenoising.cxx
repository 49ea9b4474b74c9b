#include "vtkImageBeltramiDenoising.h"
#include "vtkBeltramiSettings.h"

#include "vtkBeltramiGraphFlow.h"
#include "vtkBeltramiPieces.h"
#include "vtkBeltramiSurface.h"

#include "Flows/ColorSpace.h"
#include "Flows/TensorSpace.h"
#include "Flows/GraphFlow.h"
#include "Support/LargeBuffer.h"
#include "Support/Parallel.h"

#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkExtentTranslator.h>
#include <vtkInformationIntegerRequestKey.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <type_traits>
#include <vector>

BELTRAMI_SAME_ENUM(vtkImageBeltramiDenoising::EXPLICIT, beltrami::GraphFlowIntegration::Explicit);
BELTRAMI_SAME_ENUM(vtkImageBeltramiDenoising::SEMI_IMPLICIT, beltrami::GraphFlowIntegration::SemiImplicit);
BELTRAMI_SAME_ENUM(vtkImageBeltramiDenoising::REFLECT, beltrami::GridBoundary::Reflect);
BELTRAMI_SAME_ENUM(vtkImageBeltramiDenoising::LINEAR, beltrami::GridBoundary::Linear);

vtkStandardNewMacro(vtkImageBeltramiDenoising);

namespace
{

/// Copies `count` tuples of the first `used` of `nc` components into doubles, scaled.
template <typename T>
void Extract(const T* src, vtkIdType count, int nc, int used, double scale, double* dst, int threads)
{
  beltrami::ParallelFor(count, threads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end; ++i)
    {
      for (int k = 0; k < used; ++k)
      {
        dst[i * used + k] = scale * static_cast<double>(src[i * nc + k]);
      }
    }
  });
}

/// Writes the output extent of the result (components >= used: copied from
/// the input, e.g. an RGBA alpha), un-normalised, rounded for integers.
/// Rows in parallel where only the smoothed components are written (the
/// others are read through the input array's GetComponent, on one thread).
template <typename T>
void Store(T* dst, const int* outExt, const int* inExt, int nc, int used, double range,
  const double* values, vtkDataArray* input, int threads)
{
  const std::int64_t width = outExt[1] - outExt[0] + 1, height = outExt[3] - outExt[2] + 1;
  const std::int64_t rows = height * (outExt[5] - outExt[4] + 1);
  if (used == nc && std::equal(outExt, outExt + 6, inExt)) // every value smoothed, same extent: in order
  {
    beltrami::ParallelFor(rows * width * nc, threads, [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t j = begin; j < end; ++j)
      {
        dst[j] = vtkBeltramiGraphFlow::ToValue<T>(range * values[j]);
      }
    });
    return;
  }
  beltrami::ParallelFor(rows, used < nc ? 1 : threads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t r = begin; r < end; ++r)
    {
      int ijk[3] = { outExt[0], outExt[2] + static_cast<int>(r % height), outExt[4] + static_cast<int>(r / height) };
      for (vtkIdType o = r * width; o < (r + 1) * width; ++o, ++ijk[0])
      {
        const vtkIdType i = vtkBeltramiGraphFlow::ExtentIndex(inExt, ijk);
        for (int k = 0; k < nc; ++k)
        {
          const double v = k < used ? range * values[i * used + k] : input->GetComponent(i, k);
          dst[o * nc + k] = vtkBeltramiGraphFlow::ToValue<T>(v);
        }
      }
    }
  }, {}, 0, 16);
}

/// The values the core smooths: `Used` components per pixel; colours
/// normalised to [0, 1] by the range of their integer type, in L*u*v* when
/// `Luv` (the noise-level and least-risk stops measure in RGB); symmetric
/// tensors in log coordinates when `LogTensor` (measured back as tensors).
struct FlowValues
{
  beltrami::UninitializedVector<double> Values; // (every value read from the array)
  /// Where the output array can hold the values as the core smooths them
  /// (doubles, every component smoothed, the input's extent): that array,
  /// smoothed in place, without an array of the values besides it and a
  /// pass to store them.
  vtkSmartPointer<vtkDataArray> Output;
  double* Data = nullptr; // the values: Output's, else Values'
  int Used = 0;
  double Range = 1.0;
  bool Luv = false;
  bool LogTensor = false;
  std::string Name;
};

/// Reads `array` as the core's values (into the output array where it can
/// hold them and `sameExtent`: the output's extent is the input's); false
/// (after an error) when it cannot be smoothed.
bool ReadValues(vtkImageBeltramiDenoising* self, vtkDataArray* array, vtkIdType count, bool sameExtent, FlowValues& v)
{
  const int nc = array->GetNumberOfComponents();
  const char* name = array->GetName() ? array->GetName() : "";
  if (array->GetNumberOfTuples() != count)
  {
    vtkErrorWithObjectMacro(self, "The array '" << name << "' has " << array->GetNumberOfTuples()
                                                << " tuples for " << count << " points.");
    return false;
  }
  const int space = self->GetColorSpace();
  const bool integral = array->GetDataType() != VTK_FLOAT && array->GetDataType() != VTK_DOUBLE;
  const bool color = space == vtkImageBeltramiDenoising::RGB || space == vtkImageBeltramiDenoising::LUV ||
    (space == vtkImageBeltramiDenoising::AUTOMATIC && array->GetDataType() == VTK_UNSIGNED_CHAR &&
      (nc == 3 || nc == 4));
  if (color && nc != 3 && nc != 4)
  {
    vtkErrorWithObjectMacro(self, "Colour spaces need 3 (RGB) or 4 (RGBA) components; '"
      << name << "' has " << nc << ". The output is the input.");
    return false;
  }
  v.LogTensor = space == vtkImageBeltramiDenoising::LOG_EUCLIDEAN;
  v.Name = name;
  if (v.LogTensor && nc != 6)
  {
    vtkErrorWithObjectMacro(self, "Log-Euclidean smoothing needs symmetric tensors of 6 components (XX, YY, ZZ, "
      "XY, YZ, XZ); '" << name << "' has " << nc << ". The output is the input.");
    return false;
  }
  v.Used = color ? 3 : nc;
  if (v.Used > 6)
  {
    vtkErrorWithObjectMacro(self, "At most 6 components can be smoothed together; '"
      << name << "' has " << nc << ". The output is the input.");
    return false;
  }
  v.Luv = space == vtkImageBeltramiDenoising::LUV;
  v.Range = color && integral ? array->GetDataTypeMax() : 1.0;
  if (sameExtent && array->GetDataType() == VTK_DOUBLE && v.Used == nc && !v.Luv && !v.LogTensor)
  {
    v.Output = vtkBeltramiSurface::NewArray(VTK_DOUBLE, array->GetName(), nc, count);
    v.Data = static_cast<double*>(v.Output->GetVoidPointer(0));
  }
  else
  {
    v.Values.resize(static_cast<std::size_t>(count) * v.Used);
    v.Data = v.Values.data();
  }
  if (array->HasStandardMemoryLayout())
  {
    switch (array->GetDataType())
    {
      vtkTemplateMacro(Extract(static_cast<const VTK_TT*>(array->GetVoidPointer(0)), count, nc, v.Used,
        1.0 / v.Range, v.Data, self->GetNumberOfThreads()));
      default:
        vtkErrorWithObjectMacro(self, "Unsupported array type " << array->GetDataTypeAsString() << ".");
        return false;
    }
  }
  else
  {
    for (vtkIdType i = 0; i < count; ++i)
    {
      for (int k = 0; k < v.Used; ++k)
      {
        v.Data[i * v.Used + k] = array->GetComponent(i, k) / v.Range;
      }
    }
  }
  if (v.Luv)
  {
    beltrami::RGBToLuv(v.Data, count, 3, self->GetNumberOfThreads());
  }
  return true;
}

/// Runs the flow on the values: the pixel grid of a 2D image, or the voxels
/// of a 3D image (ImageGrid::Volume).
beltrami::GraphFlowResult RunFlow(vtkImageBeltramiDenoising* self, vtkImageData* input,
  const vtkBeltramiGraphFlow::ImageGrid& grid, const std::vector<std::uint8_t>& fixed, FlowValues& v,
  const beltrami::GridPiece* piece)
{
  beltrami::GraphFlowOptions options = vtkBeltramiGraphFlow::Options(self);
  options.Boundary = static_cast<beltrami::GridBoundary>(self->GetBoundaryHandling());
  const vtkIdType count = input->GetNumberOfPoints();
  if (v.Luv)
  {
    const int threads = self->GetNumberOfThreads();
    options.ToNoiseSpace = [count, threads](double* x) { beltrami::LuvToRGB(x, count, 3, threads); };
    options.FromNoiseSpace = [count, threads](double* x) { beltrami::RGBToLuv(x, count, 3, threads); };
  }
  if (v.LogTensor)
  {
    vtkBeltramiGraphFlow::ToLogEuclidean(self, v.Name.c_str(), v.Data, count, self->GetNumberOfThreads(),
      options, piece ? piece->Split : nullptr);
  }
  self->UpdateProgress(0.0);
  const beltrami::ProgressCallback progress = [self](double fraction) {
    self->UpdateProgress(fraction);
    return !self->GetAbortExecute();
  };
  const std::uint8_t* mask = fixed.empty() ? nullptr : fixed.data();
  const beltrami::GraphFlowResult result = grid.Volume
    ? beltrami::RunVolumeGraphFlow(grid.Voxels, v.Used, v.Data, mask, options, progress, piece)
    : beltrami::RunImageGraphFlow(grid.Pixels, v.Used, v.Data, mask, options, progress, piece);
  const std::string warning = vtkBeltramiGraphFlow::RunWarnings(options, result);
  if (!warning.empty() && result.Error.empty() && result.Completed && (!piece || piece->Split->Rank() == 0))
  {
    vtkWarningWithObjectMacro(self, << warning);
  }
  return result;
}

/// Writes the smoothed values over the output extent (the input's name and
/// type, back from L*u*v*) and the report.
void WriteOutput(vtkImageBeltramiDenoising* self, vtkImageData* input, vtkImageData* output,
  vtkDataArray* array, const int* inExt, FlowValues& v, const beltrami::GraphFlowResult& result)
{
  if (v.Luv)
  {
    beltrami::LuvToRGB(v.Data, input->GetNumberOfPoints(), 3, self->GetNumberOfThreads());
  }
  if (v.LogTensor)
  {
    beltrami::LogToSymmetricTensors(v.Data, input->GetNumberOfPoints(), 6, self->GetNumberOfThreads());
  }
  vtkSmartPointer<vtkDataArray> smoothed = v.Output;
  if (!smoothed)
  {
    int outExt[6];
    output->GetExtent(outExt);
    const int nc = array->GetNumberOfComponents();
    smoothed = vtkBeltramiSurface::NewArray(array->GetDataType(), array->GetName(), nc, output->GetNumberOfPoints());
    switch (smoothed->GetDataType())
    {
      vtkTemplateMacro(Store(static_cast<VTK_TT*>(smoothed->GetVoidPointer(0)), outExt, inExt, nc, v.Used,
        v.Range, v.Data, array, self->GetNumberOfThreads()));
    }
  }
  vtkBeltramiGraphFlow::ReplaceArray(input, output, array, smoothed);
  vtkBeltramiGraphFlow::AddReport(output->GetFieldData(), result);
}

/// RequestData's checks and reads of the input (its extents `inExt`, and
/// `outExt` to produce; `array`: input array 0): the mask and the values;
/// false after an error.
bool ReadInput(vtkImageBeltramiDenoising* self, vtkImageData* input, const int* inExt, const int* outExt,
  const vtkBeltramiGraphFlow::ImageGrid& grid, vtkDataArray* array, int association,
  std::vector<std::uint8_t>& fixed, FlowValues& v)
{
  for (int a = 0; a < 3; ++a)
  {
    if (outExt[2 * a] < inExt[2 * a] || outExt[2 * a + 1] > inExt[2 * a + 1])
    {
      vtkErrorWithObjectMacro(self, "The input extent does not cover the requested extent: the output is the input.");
      return false;
    }
  }
  if (grid.Volume && input->GetNumberOfPoints() > std::numeric_limits<beltrami::Index>::max() / 8)
  {
    vtkErrorWithObjectMacro(self, "The 3D image has " << input->GetNumberOfPoints() << " voxels: too many for one piece of the "
                                      << "tetrahedral flow; stream it in pieces. The output is the input.");
    return false;
  }
  if (!vtkBeltramiGraphFlow::IsPointArray(self, array, association))
  {
    return false;
  }
  std::string error;
  fixed = self->GetUseFixedPointsArray()
    ? vtkBeltramiSurface::SelectedPointMask(
        self, input, vtkImageBeltramiDenoising::FIXED_POINTS_ARRAY, "fixed-pixel mask", error)
    : std::vector<std::uint8_t>();
  if (!error.empty())
  {
    vtkErrorWithObjectMacro(self, << error << " The output is the input.");
    return false;
  }
  return ReadValues(self, array, input->GetNumberOfPoints(), std::equal(outExt, outExt + 6, inExt), v);
}

/// A run split over the ranks (collective): the owners of the samples
/// (vtkBeltramiPieces::BuildGridPartition), the piece of the whole extent,
/// and the settings of the values agreed (an empty piece has no array to
/// read them from).  False after an error.
bool SplitGrid(vtkImageBeltramiDenoising* self, vtkBeltramiPieces& pieces,
  const vtkBeltramiGraphFlow::ImageGrid& grid, const int* whole, const int* inExt, const int* outExt, bool empty,
  FlowValues& v, beltrami::GridPiece& piece)
{
  std::string error;
  const int none[6] = { 0, -1, 0, -1, 0, -1 };
  if (!pieces.BuildGridPartition(empty ? none : inExt, empty ? none : outExt, error)) // collective
  {
    vtkErrorWithObjectMacro(self, "Cannot split the flow over the ranks: " << error << ". The output is the input.");
    return false;
  }
  piece.Split = pieces.Split();
  const int axes[3] = { grid.Volume ? 0 : grid.Axis0, grid.Volume ? 1 : grid.Axis1, 2 };
  for (int a = 0; a < (grid.Volume ? 3 : 2); ++a)
  {
    piece.Whole[a] = whole[2 * axes[a] + 1] - whole[2 * axes[a]] + 1;
    piece.Origin[a] = empty ? 0 : inExt[2 * axes[a]] - whole[2 * axes[a]];
  }
  // What an empty piece cannot read from its array: the others' settings.
  const beltrami::Partition* rows = piece.Split;
  v.Used = static_cast<int>(rows->Max(v.Used));
  v.Range = rows->Max(v.Range);
  v.Luv = rows->Max(v.Luv ? 1.0 : 0.0) > 0.0;
  v.LogTensor = rows->Max(v.LogTensor ? 1.0 : 0.0) > 0.0;
  return true;
}

} // namespace

vtkImageBeltramiDenoising::vtkImageBeltramiDenoising()
{
  beltrami::GraphFlowOptions defaults;
  vtkBeltramiGraphFlow::CopySettings(this, defaults, vtkBeltramiCopy::FromCore);
  BeltramiCopySetting(this->BoundaryHandling, defaults.Boundary, vtkBeltramiCopy::FromCore);
  this->SetInputArrayToProcess(
    SMOOTHED_ARRAY, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

bool vtkImageBeltramiDenoising::IsLocal() const
{
  return this->Integration == EXPLICIT && !this->AdaptiveTimeStep && this->NoiseLevel <= 0.0 &&
    this->StoppingRule == FIXED_ITERATIONS && this->ContrastScale > 0.0;
}

int vtkImageBeltramiDenoising::RequestInformation(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // Any sub-extent can be produced: a request for piece k of n (ParaView's
  // MPI ranks) is split into an extent by the executive, as for readers.
  outputVector->GetInformationObject(0)->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  return this->Superclass::RequestInformation(request, inputVector, outputVector);
}

int vtkImageBeltramiDenoising::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // One ring of neighbours per explicit step; or, where the flow needs the
  // whole image and it is split over ranks that can solve together (the
  // whole image asked for, one piece per rank, as in pvbatch and
  // pvserver), one ring around each rank's piece (the ranks then solve
  // together: SolveOverRanks); else everything.
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  int whole[6], ext[6];
  inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), ext);
  this->SolveOverRanks =
    !this->IsLocal() && vtkBeltramiPieces::CanSolveTogether(outInfo) && std::equal(ext, ext + 6, whole);
  if (this->SolveOverRanks)
  {
    // Slabs of whole rows where the image is deep enough (16 cells a piece
    // along z, else y): the kernels go row by row, and a row cut in parts
    // pays its fixed cost per part.
    const int pieces = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES());
    for (const int axis : { vtkExtentTranslator::Z_SLAB_MODE, vtkExtentTranslator::Y_SLAB_MODE })
    {
      if (whole[2 * axis + 1] - whole[2 * axis] >= 16 * pieces)
      {
        vtkInformationIntegerKey* mode = vtkExtentTranslator::UPDATE_SPLIT_MODE();
        outInfo->Set(mode, axis);
        break;
      }
    }
  }
  vtkBeltramiGraphFlow::RequestImageExtent(
    inInfo, outInfo, this->IsLocal() ? this->NumberOfIterations : this->SolveOverRanks ? 1 : -1);
  return 1;
}

int vtkImageBeltramiDenoising::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  // A run split over the ranks: every rank goes through the same collective
  // steps (an empty piece too), and agrees on errors before them.
  vtkBeltramiPieces pieces;
  pieces.SetCollective(this->SolveOverRanks);
  if (!pieces.AllAgree(input && output))
  {
    vtkErrorMacro("Input and output must be vtkImageData.");
    return 0;
  }
  int outExt[6], whole[6], inExt[6];
  outputVector->GetInformationObject(0)->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), outExt);
  inputVector[0]->GetInformationObject(0)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  input->GetExtent(inExt);
  // A defined output first: the input, cropped to the requested extent.
  output->ShallowCopy(input);
  if (!std::equal(inExt, inExt + 6, outExt) && input->GetNumberOfPoints() > 0)
  {
    output->Crop(outExt);
  }
  const bool empty = input->GetNumberOfPoints() == 0 || output->GetNumberOfPoints() == 0;
  if (empty && !this->SolveOverRanks)
  {
    return 1; // empty image or piece: nothing to smooth
  }
  if (!empty)
  {
    output->GetExtent(outExt);
  }
  FlowValues v;
  std::vector<std::uint8_t> fixed;
  int association = -1;
  vtkDataArray* array = empty ? nullptr : this->GetInputArrayToProcess(SMOOTHED_ARRAY, inputVector, association);
  const vtkBeltramiGraphFlow::ImageGrid grid = vtkBeltramiGraphFlow::GridOf(input, whole, inExt);
  if (!pieces.AllAgree(empty || ReadInput(this, input, inExt, outExt, grid, array, association, fixed, v)))
  {
    return 0;
  }
  beltrami::GridPiece piece;
  if (this->SolveOverRanks && !SplitGrid(this, pieces, grid, whole, inExt, outExt, empty, v, piece))
  {
    return 0;
  }
  const beltrami::GraphFlowResult result = RunFlow(this, input, grid, fixed, v, piece.Split ? &piece : nullptr);
  if (!result.Error.empty())
  {
    vtkErrorMacro(<< result.Error << ". The output is the input.");
    return 0;
  }
  if (!result.Completed || empty)
  {
    return 1; // aborted, or an empty piece: the output is the input
  }
  WriteOutput(this, input, output, array, inExt, v, result);
  if (piece.Split)
  {
    pieces.AddDistribution(output->GetFieldData(), "FlowDistribution");
  }
  return 1;
}

void vtkImageBeltramiDenoising::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  vtkBeltramiGraphFlow::PrintSettings(this, os, indent);
  os << indent << "ColorSpace: " << this->ColorSpace << "\n";
  os << indent << "BoundaryHandling: " << this->BoundaryHandling << "\n";
}
