// The settings of the graph-flow filters (vtkImageBeltramiDenoising,
// vtkSurfaceDataDenoising, vtkTetrahedralBeltramiDenoising), written once:
// each filter's class body says vtkBeltramiGraphFlowSettingsMacro() in its
// public part and vtkBeltramiGraphFlowMembersMacro() in its protected part.
// The values start from the core's GraphFlowOptions (vtkBeltramiGraphFlow::
// CopySettings in the constructors), so each default has one source.
// The mesh filters add vtkBeltramiMeshUnitsMacro() (Units: images use
// their spacing).
#ifndef vtkBeltramiGraphFlowSettings_h
#define vtkBeltramiGraphFlowSettings_h

#include "vtkSetGet.h"

// clang-format off
#define vtkBeltramiGraphFlowSettingsMacro()                                                       \
  /** The input arrays (SetInputArrayToProcess index). */                                        \
  enum InputArrays                                                                                \
  {                                                                                               \
    SMOOTHED_ARRAY = 0,    /* the point array to smooth (default: the active scalars) */         \
    FIXED_POINTS_ARRAY = 1 /* optional: non-zero values mark points kept as they are */          \
  };                                                                                              \
  enum IntegrationType                                                                            \
  {                                                                                               \
    EXPLICIT = 0,                                                                                 \
    SEMI_IMPLICIT = 1                                                                             \
  };                                                                                              \
  enum StoppingRuleType                                                                           \
  {                                                                                               \
    FIXED_ITERATIONS = 0, /* NumberOfIterations steps */                                          \
    NOISE_LEVEL = 1,      /* when the RMS change reaches the noise level (discrepancy) */         \
    MINIMUM_RISK = 2      /* at the least estimated error (Monte-Carlo SURE) */                   \
  };                                                                                              \
  /** 0: automatic (relative to the noise level and the length unit). */                         \
  vtkSetClampMacro(ContrastScale, double, 0.0, VTK_DOUBLE_MAX);                                   \
  vtkGetMacro(ContrastScale, double);                                                             \
  vtkSetClampMacro(EdgeContrast, double, -1.0, 10.0);                                             \
  vtkGetMacro(EdgeContrast, double);                                                              \
  vtkSetClampMacro(Integration, int, EXPLICIT, SEMI_IMPLICIT);                                    \
  vtkGetMacro(Integration, int);                                                                  \
  vtkSetClampMacro(TimeStep, double, 0.0, VTK_DOUBLE_MAX);                                        \
  vtkGetMacro(TimeStep, double);                                                                  \
  vtkSetMacro(AdaptiveTimeStep, bool);                                                            \
  vtkGetMacro(AdaptiveTimeStep, bool);                                                            \
  vtkBooleanMacro(AdaptiveTimeStep, bool);                                                        \
  vtkSetClampMacro(NumberOfIterations, int, 0, VTK_INT_MAX);                                      \
  vtkGetMacro(NumberOfIterations, int);                                                           \
  vtkSetClampMacro(StoppingRule, int, FIXED_ITERATIONS, MINIMUM_RISK);                            \
  vtkGetMacro(StoppingRule, int);                                                                 \
  vtkSetClampMacro(MaximumNumberOfIterations, int, 1, VTK_INT_MAX);                               \
  vtkGetMacro(MaximumNumberOfIterations, int);                                                    \
  /** 0: estimated from the data. */                                                              \
  vtkSetClampMacro(NoiseLevel, double, 0.0, VTK_DOUBLE_MAX);                                      \
  vtkGetMacro(NoiseLevel, double);                                                                \
  vtkSetClampMacro(NumberOfThreads, int, 0, VTK_INT_MAX);                                         \
  vtkGetMacro(NumberOfThreads, int);                                                              \
  /** Whether the mask selected as input array 1 is used (default on; nothing */                 \
  /** selected = no mask).  ParaView's panel starts with it off, because it */                   \
  /** preselects an array of the input for every array selection. */                            \
  vtkSetMacro(UseFixedPointsArray, bool);                                                         \
  vtkGetMacro(UseFixedPointsArray, bool);                                                         \
  vtkBooleanMacro(UseFixedPointsArray, bool)

#define vtkBeltramiMeshUnitsMacro()                                                               \
  enum UnitsType                                                                                  \
  {                                                                                               \
    MEAN_EDGE_LENGTH = 0,                                                                         \
    PHYSICAL = 1                                                                                  \
  };                                                                                              \
  vtkSetClampMacro(Units, int, MEAN_EDGE_LENGTH, PHYSICAL);                                       \
  vtkGetMacro(Units, int)

#define vtkBeltramiGraphFlowMembersMacro()                                                        \
  friend class vtkBeltramiGraphFlow;                                                              \
  double ContrastScale;                                                                           \
  double EdgeContrast;                                                                            \
  int Integration;                                                                                \
  double TimeStep;                                                                                \
  bool AdaptiveTimeStep;                                                                          \
  int NumberOfIterations;                                                                         \
  int StoppingRule;                                                                               \
  int MaximumNumberOfIterations;                                                                  \
  double NoiseLevel;                                                                              \
  int Units;                                                                                      \
  int NumberOfThreads;                                                                            \
  bool UseFixedPointsArray = true
// clang-format on

#endif
// VTK-HeaderTest-Exclude: vtkBeltramiGraphFlowSettings.h
