// The Helmholtz-Hodge decomposition of vector fields on surfaces
// (Mesh/VectorFields): spherical-harmonic fields recovered with errors that
// fall linearly with the edge length, the torus' harmonic fields, exact
// orthogonality, exact recovery of discrete gradients and rotated gradients,
// the boundary conditions of open surfaces, the multigrid solve against
// the factorization, and coordinates and fields far from unit size.
#include "TestMeshes.h"

#include "Mesh/VectorFields.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>

namespace beltrami
{
namespace
{

using Eigen::Vector3d;

/// 3 random normal components per triangle of m (a field, not tangent).
std::vector<double> RandomField(const test::Mesh& m, unsigned seed)
{
  std::vector<double> field(m.Triangles.size());
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  for (double& x : field)
  {
    x = normal(rng);
  }
  return field;
}

/// values times factor.
std::vector<double> Scaled(std::vector<double> values, double factor)
{
  for (double& x : values)
  {
    x *= factor;
  }
  return values;
}

/// Per triangle: the centroid and the area.
struct Centroids
{
  std::vector<Vector3d> Points;
  std::vector<double> Areas;
  explicit Centroids(const test::Mesh& m)
  {
    for (std::size_t t = 0; t < m.Triangles.size(); t += 3)
    {
      const Vector3d a = m.Point(m.Triangles[t]), b = m.Point(m.Triangles[t + 1]), c = m.Point(m.Triangles[t + 2]);
      Points.push_back((a + b + c) / 3.0);
      Areas.push_back(0.5 * (b - a).cross(c - a).norm());
    }
  }
};

/// The relative L2 distance (area-weighted, per triangle) of `field` to `exact`.
double RelativeError(const Centroids& c, const std::vector<double>& field, const std::vector<Vector3d>& exact)
{
  double error = 0.0, size = 0.0;
  for (std::size_t t = 0; t < exact.size(); ++t)
  {
    error += c.Areas[t] * (Vector3d(&field[3 * t]) - exact[t]).squaredNorm();
    size += c.Areas[t] * exact[t].squaredNorm();
  }
  return std::sqrt(error / size);
}

std::vector<double> Flatten(const std::vector<Vector3d>& v)
{
  std::vector<double> out;
  for (const Vector3d& x : v)
  {
    out.insert(out.end(), { x[0], x[1], x[2] });
  }
  return out;
}

/// On the unit sphere: u = x y (degree 2, Laplace u = -6 u) and
/// v = 5 z^3 - 3 z (degree 3, Laplace v = -12 v), their tangent gradients at
/// the projection p of a point.
double U(const Vector3d& p) { return p[0] * p[1]; }
double V(const Vector3d& p) { return 5 * p[2] * p[2] * p[2] - 3 * p[2]; }
Vector3d Tangent(const Vector3d& p, const Vector3d& gradient) { return gradient - gradient.dot(p) * p; }
Vector3d GradU(const Vector3d& p) { return Tangent(p, Vector3d(p[1], p[0], 0)); }
Vector3d GradV(const Vector3d& p) { return Tangent(p, Vector3d(0, 0, 15 * p[2] * p[2] - 3)); }

struct SphereErrors
{
  double EdgeLength, CurlFree, DivergenceFree, Harmonic, Divergence, Curl, Orthogonality;
};

SphereErrors DecomposeOnSphere(int levels)
{
  const test::Mesh m = test::OctahedronSphere(levels);
  const MeshTopology topo = m.Topology();
  const Centroids c(m);
  std::vector<Vector3d> gradient, rotated, field;
  for (const Vector3d& x : c.Points)
  {
    const Vector3d p = x.normalized();
    gradient.push_back(GradU(p));
    rotated.push_back(p.cross(GradV(p)));
    field.push_back(gradient.back() + rotated.back());
  }
  VectorFieldDecomposition r;
  DecomposeVectorField(topo, m.Points.data(), Flatten(field).data(), VectorFieldOptions(), r);
  EXPECT_TRUE(r.Converged);
  SphereErrors e;
  e.EdgeLength = (m.Point(m.Triangles[0]) - m.Point(m.Triangles[1])).norm();
  e.CurlFree = RelativeError(c, r.CurlFree, gradient);
  e.DivergenceFree = RelativeError(c, r.DivergenceFree, rotated);
  e.Harmonic = std::sqrt(r.Energy[3] / r.Energy[0]);
  double dError = 0, dSize = 0, cError = 0, cSize = 0;
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    const Vector3d p = m.Point(i);
    dError += std::pow(r.Divergence[i] + 6 * U(p), 2);
    dSize += std::pow(6 * U(p), 2);
    cError += std::pow(r.Curl[i] + 12 * V(p), 2);
    cSize += std::pow(12 * V(p), 2);
  }
  e.Divergence = std::sqrt(dError / dSize);
  e.Curl = std::sqrt(cError / cSize);
  e.Orthogonality = std::max({ std::abs(r.InnerProducts[0]), std::abs(r.InnerProducts[1]),
                      std::abs(r.InnerProducts[2]) }) / r.Energy[0];
  return e;
}

TEST(VectorFields, SphericalHarmonicPartsConvergeLinearly)
{
  std::vector<SphereErrors> errors;
  for (int levels = 4; levels <= 7; ++levels) // 1k, 4k, 16k, 66k vertices
  {
    errors.push_back(DecomposeOnSphere(levels));
    const SphereErrors& e = errors.back();
    std::printf("h %.4f: curl-free %.3e  divergence-free %.3e  harmonic %.3e  div %.3e  curl %.3e  "
                "orthogonality %.1e\n",
      e.EdgeLength, e.CurlFree, e.DivergenceFree, e.Harmonic, e.Divergence, e.Curl, e.Orthogonality);
    EXPECT_LT(e.Orthogonality, 1e-8);
    EXPECT_LT(e.Harmonic, 1e-8) << "a sphere has no harmonic fields";
  }
  for (std::size_t k = 1; k < errors.size(); ++k)
  {
    // At least linear: the error at least halves when the edge length does.
    const double halving = errors[k - 1].EdgeLength / errors[k].EdgeLength;
    EXPECT_NEAR(halving, 2.0, 0.1);
    EXPECT_GT(errors[k - 1].CurlFree / errors[k].CurlFree, 0.95 * halving);
    EXPECT_GT(errors[k - 1].DivergenceFree / errors[k].DivergenceFree, 0.95 * halving);
  }
  EXPECT_LT(errors.back().CurlFree, 0.01);
  EXPECT_LT(errors.back().DivergenceFree, 0.01);
  EXPECT_LT(errors.back().Divergence, 0.01);
  EXPECT_LT(errors.back().Curl, 0.01);
}

/// The rotation-angle gradient of a torus of revolution about z: tangent to
/// the large circles, of length 1/rho.
std::vector<Vector3d> AngleGradient(const Centroids& c)
{
  std::vector<Vector3d> field;
  for (const Vector3d& p : c.Points)
  {
    const double rho2 = p[0] * p[0] + p[1] * p[1];
    field.push_back(Vector3d(-p[1], p[0], 0) / rho2);
  }
  return field;
}

TEST(VectorFields, TheTorusAngleGradientIsHarmonic)
{
  double previous = 1.0;
  for (const int n : { 40, 80, 160 }) // 2.4k, 9.6k, 38k vertices
  {
    const test::Mesh m = test::Torus(1.0, 0.4, 2 * n, n / 2 + n / 4, 0.2, 7);
    const Centroids c(m);
    const std::vector<Vector3d> field = AngleGradient(c);
    VectorFieldDecomposition r;
    DecomposeVectorField(m.Topology(), m.Points.data(), Flatten(field).data(), VectorFieldOptions(), r);
    const double others = std::sqrt((r.Energy[1] + r.Energy[2]) / r.Energy[0]);
    const double harmonic = RelativeError(c, r.Harmonic, field);
    std::printf("%d vertices: other parts %.3e of the field, harmonic part off by %.3e\n", m.NumberOfVertices(),
      others, harmonic);
    EXPECT_LT(others, previous);
    previous = others;
    if (n == 160)
    {
      EXPECT_LT(others, 0.01);
      EXPECT_LT(harmonic, 0.01);
    }
  }
}

/// The Gram matrix of the harmonic parts of random fields: its rank is the
/// dimension of the harmonic fields.
Eigen::VectorXd HarmonicGramEigenvalues(const test::Mesh& m, int fields, const VectorFieldOptions& o = {})
{
  const MeshTopology topo = m.Topology();
  const Centroids c(m);
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  std::vector<std::vector<double>> parts;
  const VectorFieldDecomposer decomposer(topo, m.Points.data(), o); // prepared once for all the fields
  for (int k = 0; k < fields; ++k)
  {
    std::vector<double> field(m.Triangles.size());
    for (double& x : field)
    {
      x = normal(rng);
    }
    VectorFieldDecomposition r, once;
    decomposer.Decompose(field.data(), r);
    if (k == fields - 1) // the prepared decomposer gives what a decomposition from scratch gives
    {
      DecomposeVectorField(topo, m.Points.data(), field.data(), o, once);
      EXPECT_EQ(r.Harmonic, once.Harmonic);
      EXPECT_EQ(r.StreamFunction, once.StreamFunction);
    }
    EXPECT_LT(std::abs(r.InnerProducts[0]), 1e-8 * r.Energy[0]);
    EXPECT_LT(std::abs(r.InnerProducts[1]), 1e-8 * r.Energy[0]);
    EXPECT_LT(std::abs(r.InnerProducts[2]), 1e-8 * r.Energy[0]);
    parts.push_back(r.Harmonic);
  }
  Eigen::MatrixXd gram(fields, fields);
  for (int a = 0; a < fields; ++a)
  {
    for (int b = 0; b < fields; ++b)
    {
      double s = 0.0;
      for (std::size_t t = 0; t < c.Areas.size(); ++t)
      {
        s += c.Areas[t] * Vector3d(&parts[a][3 * t]).dot(Vector3d(&parts[b][3 * t]));
      }
      gram(a, b) = s;
    }
  }
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(gram).eigenvalues().reverse();
}

TEST(VectorFields, HarmonicFieldsSpanTwiceTheGenus)
{
  const Eigen::VectorXd torus = HarmonicGramEigenvalues(test::Torus(1.0, 0.4, 60, 24, 0.3, 5), 6);
  std::printf("torus: Gram eigenvalues %.3e %.3e %.3e ... %.3e\n", torus[0], torus[1], torus[2], torus[5]);
  EXPECT_GT(torus[1], 1e-3 * torus[0]);
  EXPECT_LT(torus[2], 1e-12 * torus[0]);
  const test::Mesh sphere = test::OctahedronSphere(4);
  const Centroids c(sphere);
  const std::vector<double> field = RandomField(sphere, 4);
  VectorFieldDecomposition r;
  DecomposeVectorField(sphere.Topology(), sphere.Points.data(), field.data(), VectorFieldOptions(), r);
  EXPECT_LT(r.Energy[3], 1e-20 * r.Energy[0]) << "a sphere has no harmonic fields";
  EXPECT_NEAR(r.Energy[1] + r.Energy[2] + r.Energy[3], r.Energy[0], 1e-10 * r.Energy[0]);
  // An open cylinder (genus 0, two boundary loops): 2g + b - 1 = 1 under either condition.
  for (const VectorFieldBoundary boundary :
    { VectorFieldBoundary::TangentDivergenceFree, VectorFieldBoundary::NormalCurlFree })
  {
    VectorFieldOptions o;
    o.Boundary = boundary;
    const Eigen::VectorXd cylinder = HarmonicGramEigenvalues(test::Cylinder(0.5, 1.5, 40, 30), 4, o);
    EXPECT_GT(cylinder[0], 1e-3 * cylinder.sum());
    EXPECT_LT(cylinder[1], 1e-12 * cylinder[0]);
  }
}

/// grad u and J grad u of a random function u at the vertices, per triangle.
void DiscreteGradients(const test::Mesh& m, unsigned seed, std::vector<Vector3d>& gradient, std::vector<Vector3d>& rotated)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-1, 1);
  std::vector<double> u(m.NumberOfVertices());
  for (double& x : u)
  {
    x = d(rng);
  }
  for (std::size_t t = 0; t < m.Triangles.size(); t += 3)
  {
    const Index* v = &m.Triangles[t];
    const Vector3d a = m.Point(v[0]), b = m.Point(v[1]), c = m.Point(v[2]);
    const Vector3d cross = (b - a).cross(c - a), n = cross.normalized();
    const Vector3d g = (u[v[0]] * n.cross(c - b) + u[v[1]] * n.cross(a - c) + u[v[2]] * n.cross(b - a)) / cross.norm();
    gradient.push_back(g);
    rotated.push_back(n.cross(g));
  }
}

TEST(VectorFields, DiscreteGradientsAndRotatedGradientsAreRecoveredExactly)
{
  const test::Mesh m = test::Torus(1.0, 0.3, 48, 20, 0.3, 9);
  const Centroids c(m);
  std::vector<Vector3d> gradient, rotated;
  DiscreteGradients(m, 1, gradient, rotated);
  const MeshTopology topo = m.Topology();
  VectorFieldDecomposition g, j;
  DecomposeVectorField(topo, m.Points.data(), Flatten(gradient).data(), VectorFieldOptions(), g);
  DecomposeVectorField(topo, m.Points.data(), Flatten(rotated).data(), VectorFieldOptions(), j);
  EXPECT_LT(RelativeError(c, g.CurlFree, gradient), 1e-9);
  EXPECT_LT(RelativeError(c, j.DivergenceFree, rotated), 1e-9);
  // A discrete gradient has no curl, a rotated one no divergence (exactly, weakly).
  double curl = 0, divergence = 0, gDivergence = 0;
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    curl = std::max(curl, std::abs(g.Curl[i]));
    divergence = std::max(divergence, std::abs(j.Divergence[i]));
    gDivergence = std::max(gDivergence, std::abs(g.Divergence[i]));
  }
  EXPECT_LT(curl, 1e-10 * gDivergence);
  EXPECT_LT(divergence, 1e-10 * gDivergence);
}

/// Where there are no harmonic fields: the stream function integrated
/// across the triangles is the solved one (options `o` otherwise).
void ExpectIntegratedAsSolved(const test::Mesh& m, VectorFieldOptions o, const std::string& what)
{
  const std::vector<double> field = RandomField(m, 12);
  const MeshTopology topo = m.Topology();
  VectorFieldDecomposition integrated, solved;
  DecomposeVectorField(topo, m.Points.data(), field.data(), o, integrated);
  o.Integrate = false;
  DecomposeVectorField(topo, m.Points.data(), field.data(), o, solved);
  EXPECT_TRUE(integrated.Integrated) << what;
  EXPECT_FALSE(solved.Integrated) << what;
  double difference = 0.0, size = 0.0;
  for (std::size_t e = 0; e < solved.StreamFunction.size(); ++e)
  {
    difference = std::max(difference, std::abs(integrated.StreamFunction[e] - solved.StreamFunction[e]));
    size = std::max(size, std::abs(solved.StreamFunction[e]));
  }
  EXPECT_LT(difference, 1e-9 * size) << what;
  EXPECT_LT(integrated.Energy[3], 1e-18 * integrated.Energy[0]) << what;
  EXPECT_LT(solved.Energy[3], 1e-18 * solved.Energy[0]) << what << ": no harmonic fields";
  EXPECT_NEAR(integrated.Energy[2], solved.Energy[2], 1e-9 * solved.Energy[0]) << what;
  EXPECT_GT(integrated.Energy[2], 0.1 * integrated.Energy[0]) << what;
  for (const double inner : integrated.InnerProducts)
  {
    EXPECT_LT(std::abs(inner), 1e-9 * integrated.Energy[0]) << what;
  }
}

TEST(VectorFields, IntegratedStreamFunctionEqualsTheSolvedOne)
{
  // Two closed genus-0 components (no harmonic fields).
  ExpectIntegratedAsSolved(
    test::Merged(test::OctahedronSphere(4), test::OctahedronSphere(3, 0.5), { 3.0, 0.0, 0.0 }), {}, "two spheres");
}

TEST(VectorFields, DisksIntegrateTheStreamFunctionUnderBothBoundaryConditions)
{
  // A bumpy disk (a square height field) beside a closed sphere: no
  // harmonic fields (2g + b - 1 = 0 on each), so the stream function is
  // integrated, and it is the solved one under either boundary condition
  // (fixed at 0 on the disk's boundary, or free with zero mean).
  const test::Mesh disk = test::HeightField(
    [](double x, double y) { return 0.3 * std::sin(2 * x) * std::cos(3 * y); }, 1.0, 30, 0.3, true, 5);
  const test::Mesh m = test::Merged(disk, test::OctahedronSphere(3, 0.5), { 3.0, 0.0, 0.0 });
  for (const VectorFieldBoundary boundary :
    { VectorFieldBoundary::TangentDivergenceFree, VectorFieldBoundary::NormalCurlFree })
  {
    VectorFieldOptions o;
    o.Boundary = boundary;
    ExpectIntegratedAsSolved(m, o, "disk and sphere, boundary condition " + std::to_string(static_cast<int>(boundary)));
  }
}

TEST(VectorFields, OpenSurfacesKeepOrthogonalityUnderBothBoundaryConditions)
{
  const test::Mesh m = test::Cylinder(0.5, 1.5, 40, 30);
  const MeshTopology topo = m.Topology();
  const std::vector<double> field = RandomField(m, 8);
  for (const VectorFieldBoundary boundary :
    { VectorFieldBoundary::TangentDivergenceFree, VectorFieldBoundary::NormalCurlFree })
  {
    VectorFieldOptions o;
    o.Boundary = boundary;
    VectorFieldDecomposition r;
    DecomposeVectorField(topo, m.Points.data(), field.data(), o, r);
    EXPECT_TRUE(r.Converged);
    for (const double inner : r.InnerProducts)
    {
      EXPECT_LT(std::abs(inner), 1e-9 * r.Energy[0]);
    }
    EXPECT_GT(r.Energy[3], 1e-6 * r.Energy[0]) << "an open cylinder has harmonic fields";
    if (boundary == VectorFieldBoundary::NormalCurlFree)
    {
      // u = 0 on the boundary: the curl-free part is normal to it.
      const std::vector<std::vector<Index>> loops = topo.BoundaryLoops();
      double tangential = 0, largest = 0;
      for (std::size_t t = 0; t < m.Triangles.size() / 3; ++t)
      {
        largest = std::max(largest, Vector3d(&r.CurlFree[3 * t]).norm());
        for (int k = 0; k < 3; ++k)
        {
          const Index a = m.Triangles[3 * t + k], b = m.Triangles[3 * t + (k + 1) % 3];
          if ((topo.VertexFlags(a) & VertexBoundary) && (topo.VertexFlags(b) & VertexBoundary) &&
            std::abs(m.Point(a)[2] - m.Point(b)[2]) < 1e-12)
          {
            tangential = std::max(tangential, std::abs(Vector3d(&r.CurlFree[3 * t]).dot(m.Point(b) - m.Point(a))));
          }
        }
      }
      EXPECT_EQ(loops.size(), 2u);
      EXPECT_LT(tangential, 1e-10 * largest);
    }
  }
}

/// The largest difference between two decompositions' parts, relative to
/// the largest tangent vector.
double LargestPartDifference(const VectorFieldDecomposition& a, const VectorFieldDecomposition& b)
{
  double difference = 0.0, size = 0.0;
  for (std::size_t k = 0; k < a.Tangent.size(); ++k)
  {
    size = std::max(size, std::abs(a.Tangent[k]));
    for (const auto part : { &VectorFieldDecomposition::CurlFree, &VectorFieldDecomposition::DivergenceFree,
           &VectorFieldDecomposition::Harmonic })
    {
      difference = std::max(difference, std::abs((a.*part)[k] - (b.*part)[k]));
    }
  }
  return difference / size;
}

TEST(VectorFields, MultigridSolveEqualsTheFactorizedOne)
{
  // The vertices' system by conjugate gradients on the geometric multigrid
  // (one field on a large surface) gives the factorization's parts: the
  // bunny scan (irregular, obtuse triangles), two spheres (a floating
  // potential per component), a jittered torus (the edges' system
  // factorized beside it) and an open cylinder under both conditions (fixed
  // boundary rows).
  std::string error;
  const test::Mesh bunny = test::ReadMesh("bunny00.off", error);
  ASSERT_TRUE(error.empty()) << error;
  const test::Mesh spheres = test::Merged(test::OctahedronSphere(5), test::OctahedronSphere(4, 0.5), { 3.0, 0.0, 0.0 });
  const test::Mesh torus = test::Torus(1.0, 0.3, 96, 40, 0.3, 9);
  const test::Mesh cylinder = test::Cylinder(0.5, 1.5, 80, 60);
  struct Case
  {
    const test::Mesh* M;
    VectorFieldBoundary Boundary;
  };
  for (const Case& c : { Case{ &bunny, VectorFieldBoundary::TangentDivergenceFree },
         Case{ &spheres, VectorFieldBoundary::TangentDivergenceFree },
         Case{ &torus, VectorFieldBoundary::TangentDivergenceFree },
         Case{ &cylinder, VectorFieldBoundary::TangentDivergenceFree },
         Case{ &cylinder, VectorFieldBoundary::NormalCurlFree } })
  {
    const test::Mesh& m = *c.M;
    const std::vector<double> field = RandomField(m, 21);
    const MeshTopology topo = m.Topology();
    VectorFieldOptions o;
    o.Boundary = c.Boundary;
    o.MultigridVertices = 0;
    VectorFieldDecomposition multigrid, factorized;
    DecomposeVectorField(topo, m.Points.data(), field.data(), o, multigrid);
    o.ManyFields = true;
    DecomposeVectorField(topo, m.Points.data(), field.data(), o, factorized);
    SCOPED_TRACE(m.NumberOfVertices());
    std::printf("%lld vertices: %d multigrid iterations, parts differ by %.1e of the field\n",
      static_cast<long long>(m.NumberOfVertices()), multigrid.Iterations, LargestPartDifference(multigrid, factorized));
    EXPECT_TRUE(multigrid.Converged);
    EXPECT_GT(multigrid.Iterations, 0); // solved iteratively
    EXPECT_LT(multigrid.Iterations, 40);
    EXPECT_EQ(factorized.Iterations, 0); // by the factorization
    EXPECT_LE(multigrid.Residual, o.Tolerance);
    EXPECT_LT(LargestPartDifference(multigrid, factorized), 1e-8);
    for (const double inner : multigrid.InnerProducts)
    {
      EXPECT_LT(std::abs(inner), 1e-9 * multigrid.Energy[0]);
    }
  }
}

TEST(VectorFields, SlowMultigridGivesWayToTheFactorization)
{
  // A sphere of latitude rings with many points each (a climate model's
  // latitude-longitude grid): its triangles near the poles are long and thin,
  // and the multigrid converges slowly (124 iterations at 64k points, 239 at
  // 258k: 5.0 s where the factorization took 1.1; this one 206). After at
  // most 80 iterations the factorization solves it, with the same parts.
  const test::Mesh grid = test::TwoRateSphere(1.0, 60, 480, 60, 480);
  const std::vector<double> field = RandomField(grid, 5);
  const MeshTopology topo = grid.Topology();
  VectorFieldOptions o;
  o.MultigridVertices = 0;
  VectorFieldDecomposition tried, factorized;
  DecomposeVectorField(topo, grid.Points.data(), field.data(), o, tried);
  o.ManyFields = true;
  DecomposeVectorField(topo, grid.Points.data(), field.data(), o, factorized);
  std::printf("%lld vertices: %d multigrid iterations, parts differ by %.1e of the field\n",
    static_cast<long long>(grid.NumberOfVertices()), tried.Iterations, LargestPartDifference(tried, factorized));
  EXPECT_TRUE(tried.Converged);
  EXPECT_GE(tried.Iterations, 30); // one or two passes, then the factorization
  EXPECT_LE(tried.Iterations, 80);
  EXPECT_LE(tried.Residual, o.Tolerance);
  EXPECT_LT(LargestPartDifference(tried, factorized), 1e-8);
}

TEST(VectorFields, MultigridSolveHoldsOnHostileSurfaces)
{
  // Coordinates of 1e30 and 1e-30, far off (1e6 for a sphere of 1e-3), a
  // speck of a component far away, zero-area triangles (collapsed
  // corners): the multigrid solve converges and gives the factorization's
  // parts, both leaving the same triangles out.
  const test::Mesh sphere = test::OctahedronSphere(4);
  std::vector<test::Mesh> meshes;
  for (const double scale : { 1e30, 1e-30 })
  {
    test::Mesh m = sphere;
    for (double& x : m.Points)
    {
      x *= scale;
    }
    meshes.push_back(m);
  }
  test::Mesh offset = sphere;
  for (double& x : offset.Points)
  {
    x = 1e-3 * x + 1e6;
  }
  meshes.push_back(offset);
  test::Mesh speck = test::OctahedronSphere(1, 1e-6);
  meshes.push_back(test::Merged(sphere, speck, { 1e3, 0.0, 0.0 }));
  test::Mesh collapsed = sphere;
  for (std::size_t t = 0; t < collapsed.Triangles.size(); t += 3 * 97)
  {
    const Index a = collapsed.Triangles[t], b = collapsed.Triangles[t + 1];
    for (int d = 0; d < 3; ++d)
    {
      collapsed.Points[3 * b + d] = collapsed.Points[3 * a + d];
    }
  }
  meshes.push_back(collapsed);
  for (const test::Mesh& m : meshes)
  {
    const std::vector<double> field = RandomField(m, 5);
    const MeshTopology topo = m.Topology();
    VectorFieldOptions o;
    o.MultigridVertices = 0;
    VectorFieldDecomposition multigrid, factorized;
    ASSERT_NO_THROW(DecomposeVectorField(topo, m.Points.data(), field.data(), o, multigrid));
    o.ManyFields = true;
    DecomposeVectorField(topo, m.Points.data(), field.data(), o, factorized);
    SCOPED_TRACE(m.Point(0).transpose());
    EXPECT_TRUE(multigrid.Converged);
    EXPECT_GT(multigrid.Energy[1], 0.1 * multigrid.Energy[0]); // solved, not left out
    EXPECT_EQ(multigrid.DegenerateTriangles, factorized.DegenerateTriangles);
    EXPECT_LT(LargestPartDifference(multigrid, factorized), 1e-8);
    for (const double x : multigrid.CurlFree)
    {
      ASSERT_TRUE(std::isfinite(x));
    }
  }
}

TEST(VectorFields, FarCoordinatesAndFieldsGiveTheParts)
{
  // Coordinates of 1e+-100 and 1e+-200 and vectors of 1e+-250 (squared
  // areas or norms overflow or vanish): the unit sphere's parts of the unit
  // field, scaled with the field; potentials scaled with both, divergence
  // with the field over the coordinates, energies with the squares (where
  // they are doubles).
  const test::Mesh unit = test::OctahedronSphere(4);
  const std::vector<double> field = RandomField(unit, 3);
  const MeshTopology topo = unit.Topology();
  VectorFieldDecomposition reference;
  DecomposeVectorField(topo, unit.Points.data(), field.data(), VectorFieldOptions(), reference);
  for (const double length : { 1.0, 1e200, 1e100, 1e-100, 1e-200 })
  {
    const std::vector<double> points = Scaled(unit.Points, length);
    for (const double size : { 1.0, 1e250, 1e-250 })
    {
      const std::vector<double> scaled = Scaled(field, size);
      VectorFieldDecomposition r;
      DecomposeVectorField(topo, points.data(), scaled.data(), VectorFieldOptions(), r);
      SCOPED_TRACE(length);
      SCOPED_TRACE(size);
      EXPECT_TRUE(r.Converged);
      EXPECT_EQ(r.DegenerateTriangles, 0);
      for (std::size_t k = 0; k < r.CurlFree.size(); ++k)
      {
        ASSERT_NEAR(r.CurlFree[k] / size, reference.CurlFree[k], 1e-10);
        ASSERT_NEAR(r.DivergenceFree[k] / size, reference.DivergenceFree[k], 1e-10);
      }
      for (std::size_t i = 0; std::isnormal(size * length) && std::isnormal(size / length) && i < r.Potential.size();
           ++i)
      {
        ASSERT_NEAR(r.Potential[i] / (size * length), reference.Potential[i], 1e-10);
        ASSERT_NEAR(r.Divergence[i] / (size / length), reference.Divergence[i],
          1e-10 * std::abs(reference.Divergence[i]) + 1e-12);
      }
      const double area = size * length * size * length;
      if (std::isnormal(area))
      {
        EXPECT_NEAR(r.Energy[1] / area, reference.Energy[1], 1e-12 * reference.Energy[0]);
      }
    }
  }
}

} // namespace
} // namespace beltrami
