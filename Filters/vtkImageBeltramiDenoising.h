/**
 * @class   vtkImageBeltramiDenoising
 * @brief   Edge-preserving denoising of 2D and 3D images of any number of
 *          components by the graph flows of thesis section 3.8.
 *
 * The image f (n components) is the surface (x, y, alpha f) in R^(2+n) over
 * the pixel grid, triangulated along both diagonals of every pixel cell.  The
 * flow changes the data only (a graph flow):
 *
 *     d(alpha f)/dt = E^(gamma - 1) B_bar,   E = |B_bar| / |B| in [0, 1],
 *
 * with B the Laplace-Beltrami operator of the surface (cotangent formula with
 * cotangents from dot products in R^(2+n), section 2.8.1) and B_bar its data
 * part; E is kept at least 1/W (pixel area over surface area), its value on
 * the smooth surface, where the discrete B is not quite normal to the
 * surface.  For greyscale images E = 1/W, so this is I_t = -kappa_H / W^gamma,
 * eq. 3.19; for colours and vectors the channels are coupled through the one
 * surface (eq. 3.22), never smoothed one by one.
 *
 * The defaults need no setting: the noise level is estimated from the data
 * (Flows/NoiseEstimation), the contrast scale follows from it, and the flow
 * stops at the step of least estimated error (Monte-Carlo SURE).
 * Settings:
 *  - ContrastScale alpha (section 3.8.4): data units -> spacing units.
 *    Large alpha approaches total-variation denoising, small alpha linear
 *    diffusion.  0 (default): automatic, c h / sigma with h the geometric
 *    mean of the spacing, sigma the noise level and c = 1.5 (1.0 on 3D
 *    volumes), calibrated with the least-error stop on camera, coffee,
 *    astronaut and two MRI volumes (within 0.2 dB of the best c there).
 *  - EdgeContrast gamma (eq. 3.19): 1 Beltrami flow (default), 0 El-Fallah-
 *    Ford, -1 the graph flow of mean curvature flow (Malladi-Sethian); larger
 *    values preserve even small jumps.
 *  - Integration: EXPLICIT (default; the stability limit is reported and a
 *    warning given when TimeStep exceeds it) or SEMI_IMPLICIT (weights of the
 *    current state, one conjugate-gradient solve per step, any step size).
 *  - TimeStep (squared physical units; 0, the default: 0.2 for 2D images and
 *    0.1 for 3D volumes on unit grids, scaled with the square of the spacing,
 *    below the explicit stability limits of about 0.24 and 0.12), and
 *    AdaptiveTimeStep (section 3.8.5: the step grows while the total area of
 *    the surface falls quickly and shrinks as the fall slows; explicit steps
 *    are kept below the stability limit).
 *  - StoppingRule: MINIMUM_RISK (default): the step of least estimated mean
 *    squared error to the unknown clean data, by Monte-Carlo SURE (Ramani,
 *    Blu and Unser 2008: a second run on the data plus 1% of the noise
 *    times random signs gives the divergence of the flow; twice the work);
 *    the flow runs until the estimate has risen 0.1% above its least value,
 *    or for twice the time to it, and returns the state of least estimate.  On
 *    grids of more than 2^21 values (samples x components) with explicit
 *    steps the second run covers a band of 1/16 of the planes (1/8 of the
 *    rows) plus margins, compared with the main run there: at 256^3 a sixth
 *    of the work of a second run over everything, the same stop; on a
 *    1024^2 colour photograph about half the time, a step or two later
 *    (0-0.07 dB).
 *    NOISE_LEVEL: when the RMS change of the data reaches the noise level
 *    (discrepancy principle).  FIXED_ITERATIONS: NumberOfIterations steps.
 *    The two rules end at MaximumNumberOfIterations (2000) at the latest,
 *    with a warning when it comes first.
 *  - NoiseLevel sigma (data units; colours: normalised RGB units, [0, 1]):
 *    0 (default): estimated from the data.
 *  - ColorSpace: AUTOMATIC (default: unsigned char arrays of 3 or 4
 *    components are colours, smoothed as coupled RGB; anything else is
 *    smoothed as it is), NONE (always as it is), RGB or LUV (CIE L*u*v*,
 *    perceptually uniform; the change and the error are measured back in
 *    RGB, where the noise is).  Colour images are smoothed in normalised
 *    units (RGB in [0, 1]; L*u*v* / 100), an RGBA alpha channel is passed
 *    unchanged.  RGB is the default because the noise is added there: on
 *    coffee and astronaut at noise 0.1 the automatic settings reach 28.2 and
 *    26.5 dB in RGB, 24.6 and 23.8 dB in L*u*v* (dark noise is amplified
 *    there, so one contrast scale does not fit the whole image).
 *    LOG_EUCLIDEAN: 6-component symmetric tensors (XX, YY, ZZ, XY, YZ, XZ;
 *    diffusion tensors, structure tensors) smoothed as their matrix
 *    logarithms (Arsigny et al. 2006), so the result is positive definite
 *    and averaging does not swell the tensors (equal determinants are kept
 *    exactly); the noise is estimated and measured on the tensors.
 *    Eigenvalues below 1e-6 of the field's largest are raised to it, with a
 *    warning.
 *  - BoundaryHandling beyond the image border: LINEAR (default, linear
 *    ramps are fixed points) or REFLECT (mirror, Neumann).
 * Height fields and range images: the value is a physical height; keep
 * ContrastScale 1 and the image's spacing is honoured (anisotropic too).
 *
 * Input array 0: the point array to smooth (default: the active scalars;
 * 1 to 6 components, any numeric type: the output array has the input's
 * name and type, integers rounded and clamped).  Input array 1 (optional):
 * a point array whose non-zero values mark pixels kept as they are (with
 * UseFixedPointsArray).
 * 2D images (XY, XZ and YZ slices) use the pixel-grid kernel above.  3D
 * images (section 2.8.2): the voxels are split into tetrahedra (6 per cell
 * around the cell diagonal, the split of vtkTetrahedralBeltramiDenoising's
 * voxel cells, evaluated without an explicit mesh) and the volume
 * (x, y, z, alpha f) in R^(3+n) is smoothed the same way, E =
 * V_base / V_graph; spacing honoured; the BoundaryHandling setting does not apply
 * (natural boundary).  Explicit steps are stable up to about 0.12 there
 * (half the 2D limit): the automatic TimeStep is 0.1, and explicit steps of
 * 0.1 are the documented setting for volumes (faster than semi-implicit
 * steps and no worse).  Memory per voxel: seven edge weights and two masses plus a few
 * values per component (doubles) with explicit steps; semi-implicit steps
 * add the operator and the solver's vectors (about twice as much).
 *
 * Streaming and threads: with explicit steps, a fixed time step, the
 * FIXED_ITERATIONS rule, no noise level and a given ContrastScale, every
 * step reads one ring of neighbours, so the filter
 * asks for NumberOfIterations ghost pixels around the requested extent and
 * the result of any piece equals that of the whole image, bit for bit;
 * otherwise (automatic settings, adaptive step, semi-implicit, the
 * rule-based stops: global quantities) it asks for the whole extent - except
 * where the image is split over the ranks of a distributed run (pvbatch,
 * pvserver: one piece per rank, the whole image asked for): there each rank
 * asks for its piece (slabs of whole rows where the image is deep enough)
 * and a ring of one sample, and the ranks solve together
 * (beltrami::GridPiece: the noise estimate an exact median over the ranks,
 * the stops' sums and the semi-implicit solves over all of them; the
 * numbers of a serial run; field data FlowDistribution: owned and ring
 * samples, cells, values sent per exchange; above 2^21 values the
 * least-risk probe runs on the whole split image, where a serial run probes
 * a band, so the stop may differ by a step).  The work is threaded
 * (NumberOfThreads, 0 = all) with results independent of the thread count.
 * Field data: FlowIterations (steps to the result), FlowTime, FlowRMSChange,
 * FlowArea (initial and final area of the image surface),
 * FlowSolverIterations, EstimatedNoiseLevel (the deviation of additive
 * Gaussian noise estimated from the input alone: Immerkaer's mask, median of
 * its response on the half of the pixels with the smallest gradient, its 3D
 * analogue on volumes; colours in normalised RGB units, like NoiseLevel), the
 * FlowNoiseLevel and FlowContrastScale the run used, and with the least-error
 * stop FlowEstimatedError (the estimated RMS error of the input and of the
 * result, data units).
 */
#ifndef vtkImageBeltramiDenoising_h
#define vtkImageBeltramiDenoising_h

#include "BeltramiFiltersModule.h" // export macro
#include "vtkBeltramiGraphFlowSettings.h" // the shared settings
#include "vtkImageAlgorithm.h"

class BELTRAMIFILTERS_EXPORT vtkImageBeltramiDenoising : public vtkImageAlgorithm
{
public:
  static vtkImageBeltramiDenoising* New();
  vtkTypeMacro(vtkImageBeltramiDenoising, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkBeltramiGraphFlowSettingsMacro();

  enum ColorSpaceType
  {
    AUTOMATIC = 0,
    NONE = 1,
    RGB = 2,
    LUV = 3,
    LOG_EUCLIDEAN = 4 ///< 6-component symmetric tensors, smoothed as matrix logarithms
  };
  enum BoundaryHandlingType
  {
    REFLECT = 0,
    LINEAR = 1
  };
  /// Automatic: unsigned char arrays of 3 or 4 components are colours smoothed as coupled RGB
  /// (where the noise is added), anything else is smoothed as it is. L*u*v* is perceptually
  /// uniform; the change and the error are measured back in RGB. RGB and L*u*v* treat the array as
  /// colours in [0, 1] (or the range of the integer type); an alpha channel is passed unchanged.
  /// Log-Euclidean tensors: 6-component symmetric tensors (XX, YY, ZZ, XY, YZ, XZ; e.g. diffusion
  /// tensors) smoothed as their matrix logarithms, so the result stays positive definite and does
  /// not swell (equal determinants are kept exactly); eigenvalues below 1e-6 of the largest are
  /// raised to it with a warning. Values: 0 Automatic, 1 None, 2 RGB, 3 L*u*v*, 4 Log-Euclidean
  /// tensors. Default: Automatic.
  vtkSetClampMacro(ColorSpace, int, AUTOMATIC, LOG_EUCLIDEAN);
  vtkGetMacro(ColorSpace, int);
  /// Values assumed beyond the image border: mirrored (Neumann) or linearly extrapolated (linear
  /// ramps stay exactly as they are). Values: 0 Reflect, 1 Linear. Default: Linear.
  vtkSetClampMacro(BoundaryHandling, int, REFLECT, LINEAR);
  vtkGetMacro(BoundaryHandling, int);

  /// The names these settings had before (state files and scripts keep
  /// working): Boundary = BoundaryHandling, UseFixedPixelsArray =
  /// UseFixedPointsArray.
  void SetBoundary(int boundary) { this->SetBoundaryHandling(boundary); }
  int GetBoundary() { return this->BoundaryHandling; }
  void SetUseFixedPixelsArray(bool use) { this->SetUseFixedPointsArray(use); }
  bool GetUseFixedPixelsArray() { return this->UseFixedPointsArray; }
  void UseFixedPixelsArrayOn() { this->SetUseFixedPointsArray(true); }
  void UseFixedPixelsArrayOff() { this->SetUseFixedPointsArray(false); }

protected:
  vtkImageBeltramiDenoising();
  ~vtkImageBeltramiDenoising() override = default;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  /// True when every step only reads the pixel's neighbours (no global
  /// quantity): then pieces need NumberOfIterations ghost pixels only.
  bool IsLocal() const;

  vtkBeltramiGraphFlowMembersMacro();
  int ColorSpace = AUTOMATIC;
  int BoundaryHandling;
  /// Set by RequestUpdateExtent: the image is split over ranks that solve
  /// together, each on its piece and a ring of one sample.
  bool SolveOverRanks = false;

private:
  vtkImageBeltramiDenoising(const vtkImageBeltramiDenoising&) = delete;
  void operator=(const vtkImageBeltramiDenoising&) = delete;
};

#endif
