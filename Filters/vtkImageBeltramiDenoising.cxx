#include "vtkImageBeltramiDenoising.h"
#include "vtkBeltramiSettings.h"

#include "vtkBeltramiGraphFlow.h"
#include "vtkBeltramiSurface.h"

#include "Flows/ColorSpace.h"
#include "Flows/TensorSpace.h"
#include "Flows/GraphFlow.h"
#include "Support/LargeBuffer.h"

#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkExtentTranslator.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationIntegerRequestKey.h>
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

/// The pixels of a 2D image, as seen by the core: two axes of the VTK extent.
struct GridMapping
{
  int Axis0 = 0, Axis1 = 1; // VTK axes of the grid's x and y
  int Extent[6] = { 0, -1, 0, -1, 0, -1 };
  vtkIdType Count() const
  {
    vtkIdType n = 1;
    for (int a = 0; a < 3; ++a)
    {
      n *= std::max(0, Extent[2 * a + 1] - Extent[2 * a] + 1);
    }
    return n;
  }
  /// Index in an image of extent `e` of the point with structured index ijk.
  static vtkIdType Index(const int* e, const int* ijk)
  {
    const vtkIdType nx = e[1] - e[0] + 1, ny = e[3] - e[2] + 1;
    return (ijk[0] - e[0]) + nx * ((ijk[1] - e[2]) + ny * static_cast<vtkIdType>(ijk[2] - e[4]));
  }
};

/// Copies `count` tuples of the first `used` of `nc` components into doubles, scaled.
template <typename T>
void Extract(const T* src, vtkIdType count, int nc, int used, double scale, double* dst)
{
  for (vtkIdType i = 0; i < count; ++i)
  {
    for (int k = 0; k < used; ++k)
    {
      dst[i * used + k] = scale * static_cast<double>(src[i * nc + k]);
    }
  }
}

template <typename T>
T ToValue(double v)
{
  if (std::is_integral<T>::value)
  {
    v = std::round(v);
    v = std::min<double>(std::max<double>(v, std::numeric_limits<T>::lowest()), std::numeric_limits<T>::max());
  }
  return static_cast<T>(v);
}

/// Writes the output extent of the result (components >= used: copied from
/// the input, e.g. an RGBA alpha), un-normalised, rounded for integers.
template <typename T>
void Store(T* dst, const int* outExt, const int* inExt, int nc, int used, double range,
  const double* values, vtkDataArray* input)
{
  vtkIdType o = 0;
  int ijk[3];
  for (ijk[2] = outExt[4]; ijk[2] <= outExt[5]; ++ijk[2])
  {
    for (ijk[1] = outExt[2]; ijk[1] <= outExt[3]; ++ijk[1])
    {
      for (ijk[0] = outExt[0]; ijk[0] <= outExt[1]; ++ijk[0], ++o)
      {
        const vtkIdType i = GridMapping::Index(inExt, ijk);
        for (int k = 0; k < nc; ++k)
        {
          dst[o * nc + k] =
            k < used ? ToValue<T>(range * values[i * used + k]) : ToValue<T>(input->GetComponent(i, k));
        }
      }
    }
  }
}

/// A 3D image: its voxels split into tetrahedra (6 per cell, the Kuhn split
/// of GridTetrahedra) at their physical positions, smoothed by the
/// 3-manifold flow (RunVolumeGraphFlow: no explicit mesh).
beltrami::GraphFlowResult RunVolume(vtkImageData* input, const int* ext, int components, double* values,
  const std::uint8_t* fixed, const beltrami::GraphFlowOptions& options,
  const beltrami::ProgressCallback& progress)
{
  const double* spacing = input->GetSpacing();
  beltrami::VoxelGrid grid;
  grid.Width = ext[1] - ext[0] + 1;
  grid.Height = ext[3] - ext[2] + 1;
  grid.Depth = ext[5] - ext[4] + 1;
  grid.SpacingX = std::abs(spacing[0]);
  grid.SpacingY = std::abs(spacing[1]);
  grid.SpacingZ = std::abs(spacing[2]);
  return beltrami::RunVolumeGraphFlow(grid, components, values, fixed, options, progress);
}

/// The axes of a 2D image's grid (any of XY, XZ, YZ), or none for a 3D
/// image (`volume`: the 3-manifold flow on its voxels).
GridMapping MapGrid(const int* whole, const int* inExt, bool& volume)
{
  GridMapping grid;
  std::copy(inExt, inExt + 6, grid.Extent);
  int axes[3], nAxes = 0;
  for (int a = 0; a < 3; ++a)
  {
    if (whole[2 * a + 1] > whole[2 * a])
    {
      axes[nAxes++] = a;
    }
  }
  volume = nAxes == 3;
  for (int a = 0; a < 3 && nAxes < 2; ++a)
  {
    if (nAxes == 0 || axes[0] != a)
    {
      axes[nAxes++] = a;
    }
  }
  if (!volume)
  {
    grid.Axis0 = std::min(axes[0], axes[1]);
    grid.Axis1 = std::max(axes[0], axes[1]);
  }
  return grid;
}

/// The values the core smooths: `Used` components per pixel; colours
/// normalised to [0, 1] by the range of their integer type, in L*u*v* when
/// `Luv` (the noise-level and least-risk stops measure in RGB); symmetric
/// tensors in log coordinates when `LogTensor` (measured back as tensors).
struct FlowValues
{
  beltrami::LargeVector<double> Values;
  int Used = 0;
  double Range = 1.0;
  bool Luv = false;
  bool LogTensor = false;
  std::string Name;
};

/// Reads `array` as the core's values; false (after an error) when it
/// cannot be smoothed.
bool ReadValues(vtkImageBeltramiDenoising* self, vtkDataArray* array, vtkIdType count, FlowValues& v)
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
  v.Values.resize(static_cast<std::size_t>(count) * v.Used);
  if (array->HasStandardMemoryLayout())
  {
    switch (array->GetDataType())
    {
      vtkTemplateMacro(Extract(static_cast<const VTK_TT*>(array->GetVoidPointer(0)), count, nc, v.Used,
        1.0 / v.Range, v.Values.data()));
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
        v.Values[i * v.Used + k] = array->GetComponent(i, k) / v.Range;
      }
    }
  }
  if (v.Luv)
  {
    beltrami::RGBToLuv(v.Values.data(), count, 3, self->GetNumberOfThreads());
  }
  return true;
}

/// The pixel grid of a 2D image as the core sees it.
beltrami::PixelGrid PixelsOf(vtkImageData* input, const int* inExt, const GridMapping& grid)
{
  beltrami::PixelGrid pixels;
  pixels.Width = inExt[2 * grid.Axis0 + 1] - inExt[2 * grid.Axis0] + 1;
  pixels.Height = inExt[2 * grid.Axis1 + 1] - inExt[2 * grid.Axis1] + 1;
  pixels.SpacingX = std::abs(input->GetSpacing()[grid.Axis0]);
  pixels.SpacingY = std::abs(input->GetSpacing()[grid.Axis1]);
  return pixels;
}

/// Runs the flow on the values: the pixel grid of a 2D image, or the voxels
/// of a 3D image (`volume`).
beltrami::GraphFlowResult RunFlow(vtkImageBeltramiDenoising* self, vtkImageData* input, const int* inExt,
  const GridMapping& grid, bool volume, const std::vector<std::uint8_t>& fixed, FlowValues& v)
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
    vtkBeltramiGraphFlow::ToLogEuclidean(self, v.Name.c_str(), v.Values.data(), count, self->GetNumberOfThreads(),
      options);
  }
  self->UpdateProgress(0.0);
  const beltrami::ProgressCallback progress = [self](double fraction) {
    self->UpdateProgress(fraction);
    return !self->GetAbortExecute();
  };
  const std::uint8_t* mask = fixed.empty() ? nullptr : fixed.data();
  const beltrami::PixelGrid pixels = PixelsOf(input, inExt, grid);
  const beltrami::GraphFlowResult result = volume
    ? RunVolume(input, inExt, v.Used, v.Values.data(), mask, options, progress)
    : beltrami::RunImageGraphFlow(pixels, v.Used, v.Values.data(), mask, options, progress);
  const std::string warning = vtkBeltramiGraphFlow::RunWarnings(options, result);
  if (!warning.empty() && result.Error.empty() && result.Completed)
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
    beltrami::LuvToRGB(v.Values.data(), input->GetNumberOfPoints(), 3, self->GetNumberOfThreads());
  }
  if (v.LogTensor)
  {
    beltrami::LogToSymmetricTensors(v.Values.data(), input->GetNumberOfPoints(), 6, self->GetNumberOfThreads());
  }
  int outExt[6];
  output->GetExtent(outExt);
  const int nc = array->GetNumberOfComponents();
  vtkSmartPointer<vtkDataArray> smoothed = vtk::TakeSmartPointer(vtkDataArray::CreateDataArray(array->GetDataType()));
  smoothed->SetName(array->GetName());
  smoothed->SetNumberOfComponents(nc);
  smoothed->SetNumberOfTuples(output->GetNumberOfPoints());
  switch (smoothed->GetDataType())
  {
    vtkTemplateMacro(Store(static_cast<VTK_TT*>(smoothed->GetVoidPointer(0)), outExt, inExt, nc, v.Used,
      v.Range, v.Values.data(), array));
  }
  vtkBeltramiGraphFlow::ReplaceArray(input, output, array, smoothed);
  vtkBeltramiGraphFlow::AddReport(output->GetFieldData(), result);
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
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
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
    if (!this->IsLocal())
    {
      ext[2 * a] = whole[2 * a];
      ext[2 * a + 1] = whole[2 * a + 1];
    }
    else if (ext[2 * a] <= ext[2 * a + 1])
    {
      // One ring of neighbours per explicit step.
      const int g = this->NumberOfIterations;
      ext[2 * a] = std::max(whole[2 * a], ext[2 * a] - g);
      ext[2 * a + 1] = std::min(whole[2 * a + 1], ext[2 * a + 1] + g);
    }
  }
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), ext, 6);
  return 1;
}

int vtkImageBeltramiDenoising::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  if (!input || !output)
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
  if (input->GetNumberOfPoints() == 0 || output->GetNumberOfPoints() == 0)
  {
    return 1; // empty image or piece: nothing to smooth
  }
  output->GetExtent(outExt);
  for (int a = 0; a < 3; ++a)
  {
    if (outExt[2 * a] < inExt[2 * a] || outExt[2 * a + 1] > inExt[2 * a + 1])
    {
      vtkErrorMacro("The input extent does not cover the requested extent: the output is the input.");
      return 0;
    }
  }
  bool volume = false;
  const GridMapping grid = MapGrid(whole, inExt, volume);
  if (volume && grid.Count() > std::numeric_limits<beltrami::Index>::max() / 8)
  {
    vtkErrorMacro("The 3D image has " << grid.Count() << " voxels: too many for one piece of the "
                                      << "tetrahedral flow; stream it in pieces. The output is the input.");
    return 0;
  }
  int association = -1;
  vtkDataArray* array = this->GetInputArrayToProcess(SMOOTHED_ARRAY, inputVector, association);
  if (!vtkBeltramiGraphFlow::IsPointArray(this, array, association))
  {
    return 0;
  }
  std::string error;
  const std::vector<std::uint8_t> fixed = this->UseFixedPointsArray
    ? vtkBeltramiSurface::SelectedPointMask(this, input, FIXED_POINTS_ARRAY, "fixed-pixel mask", error)
    : std::vector<std::uint8_t>();
  if (!error.empty())
  {
    vtkErrorMacro(<< error << " The output is the input.");
    return 0;
  }
  FlowValues v;
  if (!ReadValues(this, array, input->GetNumberOfPoints(), v))
  {
    return 0;
  }
  const beltrami::GraphFlowResult result = RunFlow(this, input, inExt, grid, volume, fixed, v);
  if (!result.Error.empty())
  {
    vtkErrorMacro(<< result.Error << ". The output is the input.");
    return 0;
  }
  if (!result.Completed)
  {
    return 1; // aborted: the output is the input
  }
  WriteOutput(this, input, output, array, inExt, v, result);
  return 1;
}

void vtkImageBeltramiDenoising::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  vtkBeltramiGraphFlow::PrintSettings(this, os, indent);
  os << indent << "ColorSpace: " << this->ColorSpace << "\n";
  os << indent << "BoundaryHandling: " << this->BoundaryHandling << "\n";
}
