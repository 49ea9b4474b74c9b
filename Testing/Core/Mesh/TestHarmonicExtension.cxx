// The harmonic extension of point data to new vertices (Mesh/HarmonicExtension):
// linear precision on surfaces and tetrahedral meshes, known rows untouched,
// more than 8 columns, and a non-linear field pulled to the harmonic one.
#include "TestMeshes.h"

#include "Mesh/HarmonicExtension.h"
#include "Mesh/Tetrahedra.h"

#include <gtest/gtest.h>

#include <random>

namespace beltrami
{
namespace
{

/// A linear field per column: value_c(x) = c + (c + 1) x - 2 y + 0.5 c z.
double Linear(int c, const double* p)
{
  return c + (c + 1) * p[0] - 2.0 * p[1] + 0.5 * c * p[2];
}

/// Known values on the `known` rows, 0 elsewhere (the initial guess, as the
/// TetGen filter gives it).
std::vector<double> LinearOnKnown(const std::vector<double>& points, const std::vector<std::uint8_t>& known, int columns)
{
  const std::size_t n = known.size();
  std::vector<double> values(n * columns, 0.0);
  for (std::size_t i = 0; i < n; ++i)
  {
    for (int c = 0; c < columns; ++c)
    {
      values[i * columns + c] = known[i] ? Linear(c, &points[3 * i]) : 0.0;
    }
  }
  return values;
}

TEST(HarmonicExtension, ReproducesLinearFieldsOnAFlatIrregularSurface)
{
  const test::Mesh m = test::FlatIrregular(12, 7);
  const MeshTopology topo = m.Topology();
  GraphLaplacian lap;
  AssembleSurfaceLaplacian(topo, m.Points.data(), LaplacianWeights::Cotangent, lap);
  const Index n = topo.NumberOfVertices();
  std::vector<std::uint8_t> known(n);
  Index unknown = 0;
  for (Index i = 0; i < n; ++i)
  {
    known[i] = (topo.VertexFlags(i) & VertexBoundary) != 0;
    unknown += !known[i];
  }
  ASSERT_GT(unknown, 50);
  const int columns = 11; // two blocks of the 8-column solver
  std::vector<double> values = LinearOnKnown(m.Points, known, columns);
  const std::vector<double> before = values;
  const HarmonicExtensionReport r = ExtendHarmonically(lap, known.data(), columns, values.data());
  EXPECT_TRUE(r.Converged);
  EXPECT_GT(r.Iterations, 0);
  for (Index i = 0; i < n; ++i)
  {
    for (int c = 0; c < columns; ++c)
    {
      if (known[i])
      {
        EXPECT_EQ(values[i * columns + c], before[i * columns + c]); // bit for bit
      }
      else
      {
        EXPECT_NEAR(values[i * columns + c], Linear(c, &m.Points[3 * i]), 1e-8) << i << " " << c;
      }
    }
  }
}

TEST(HarmonicExtension, ReproducesLinearFieldsInsideAJitteredTetrahedralGrid)
{
  const int nx = 7, ny = 6, nz = 5;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  std::vector<double> points;
  std::vector<std::uint8_t> known;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
      {
        const bool onBoundary = i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1;
        points.insert(points.end(), { i + (onBoundary ? 0.0 : jitter(rng)), j + (onBoundary ? 0.0 : jitter(rng)),
                                      k + (onBoundary ? 0.0 : jitter(rng)) });
        known.push_back(onBoundary);
      }
  const TetrahedralMesh mesh(nx * ny * nz, GridTetrahedra(nx, ny, nz));
  GraphLaplacian lap;
  AssembleTetrahedralLaplacian(mesh, points.data(), 3, lap);
  std::vector<double> values = LinearOnKnown(points, known, 3);
  ASSERT_TRUE(ExtendHarmonically(lap, known.data(), 3, values.data()).Converged);
  for (std::size_t i = 0; i < known.size(); ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      EXPECT_NEAR(values[i * 3 + c], Linear(c, &points[3 * i]), 1e-8);
    }
  }
}

TEST(HarmonicExtension, QuadraticFieldIsReplacedByItsHarmonicPart)
{
  // On a regular grid of [-0.5, 0.5]^2, x^2 - y^2 is harmonic: reproduced up
  // to the discretisation error.  x^2 + y^2 is not: its extension obeys the
  // maximum principle (the cotangent weights of right triangles are
  // non-negative) and stays within the boundary's range of values.
  const test::Mesh m = test::HeightField([](double, double) { return 0.0; }, 0.5, 16, 0.0, false, 1);
  const MeshTopology topo = m.Topology();
  GraphLaplacian lap;
  AssembleSurfaceLaplacian(topo, m.Points.data(), LaplacianWeights::Cotangent, lap);
  const Index n = topo.NumberOfVertices();
  std::vector<std::uint8_t> known(n);
  std::vector<double> values(2 * n);
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (Index i = 0; i < n; ++i)
  {
    known[i] = (topo.VertexFlags(i) & VertexBoundary) != 0;
    const double x = m.Points[3 * i], y = m.Points[3 * i + 1];
    values[2 * i] = x * x - y * y;
    values[2 * i + 1] = known[i] ? x * x + y * y : 0.0;
    if (known[i])
    {
      lo = std::min(lo, values[2 * i + 1]);
      hi = std::max(hi, values[2 * i + 1]);
    }
  }
  ExtendHarmonically(lap, known.data(), 2, values.data());
  double worstHarmonic = 0.0;
  for (Index i = 0; i < n; ++i)
  {
    const double x = m.Points[3 * i], y = m.Points[3 * i + 1];
    worstHarmonic = std::max(worstHarmonic, std::abs(values[2 * i] - (x * x - y * y)));
    EXPECT_GE(values[2 * i + 1], lo - 1e-12);
    EXPECT_LE(values[2 * i + 1], hi + 1e-12);
  }
  EXPECT_LT(worstHarmonic, 1e-2);
}

} // namespace
} // namespace beltrami
