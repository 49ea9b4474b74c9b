// Accuracy and invariants of the core curvature operators (thesis 2.4-2.7).
#include "TestMeshes.h"

#include "Mesh/Curvatures.h"
#include "Mesh/SurfaceOperators.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cstdio>
#include <map>

using namespace beltrami;
using test::Mesh;

namespace
{

struct Result
{
  std::vector<double> K, A, H, G, K1, K2, E1, E2, N;
  std::vector<std::uint8_t> Status;
  CurvatureReport Report;

  Eigen::Vector3d Vec(const std::vector<double>& v, Index i) const
  {
    return { v[3 * i], v[3 * i + 1], v[3 * i + 2] };
  }
};

Result Compute(const Mesh& m, CurvatureOptions options = {})
{
  const MeshTopology topo = m.Topology(options.NumberOfThreads);
  const std::size_t n = m.NumberOfVertices();
  Result r;
  for (auto* v : { &r.A, &r.H, &r.G, &r.K1, &r.K2 })
  {
    v->assign(n, -1.0);
  }
  for (auto* v : { &r.K, &r.E1, &r.E2, &r.N })
  {
    v->assign(3 * n, -1.0);
  }
  r.Status.assign(n, 255);
  CurvatureOutputs out;
  out.MeanCurvatureNormal = r.K.data();
  out.MixedArea = r.A.data();
  out.MeanCurvature = r.H.data();
  out.GaussianCurvature = r.G.data();
  out.MaximumCurvature = r.K1.data();
  out.MinimumCurvature = r.K2.data();
  out.PrincipalDirection1 = r.E1.data();
  out.PrincipalDirection2 = r.E2.data();
  out.Normals = r.N.data();
  out.Status = r.Status.data();
  r.Report = ComputeCurvatures(topo, m.Points.data(), options, out);
  return r;
}

double Sum(const std::vector<double>& v)
{
  double s = 0;
  for (double x : v)
  {
    s += x;
  }
  return s;
}

} // namespace

// Thesis 2.7.1: octahedral spheres of 258 ... 16386 vertices; the mean relative
// error is at most 0.07% for kappa_H and 1.3% for kappa_G, and falls with refinement.
TEST(Curvatures, OctahedralSpheresMatchThesisAccuracy)
{
  double previousH = 1e9, previousG = 1e9;
  for (int level = 3; level <= 6; ++level)
  {
    const double R = 2.0;
    const Mesh m = test::OctahedronSphere(level, R);
    const Result r = Compute(m);
    double errH = 0, errG = 0;
    const Index n = m.NumberOfVertices();
    for (Index i = 0; i < n; ++i)
    {
      ASSERT_EQ(r.Status[i], 0);
      errH += std::abs(r.H[i] - 1 / R) * R;
      errG += std::abs(r.G[i] - 1 / (R * R)) * R * R;
    }
    errH /= n;
    errG /= n;
    std::printf("sphere %6d vertices: mean rel. error kappa_H %.4f%%, kappa_G %.4f%%\n", n,
      100 * errH, 100 * errG);
    EXPECT_LE(errH, 0.0007) << n << " vertices";
    EXPECT_LE(errG, 0.013) << n << " vertices";
    EXPECT_LT(errH, previousH);
    EXPECT_LT(errG, previousG);
    previousH = errH;
    previousG = errG;
  }
}

TEST(Curvatures, TaubinIsLessAccurateOnSpheres)
{
  const Mesh m = test::OctahedronSphere(4);
  CurvatureOptions taubin;
  taubin.Method = CurvatureMethod::Taubin1995;
  const Result meyer = Compute(m), tau = Compute(m, taubin);
  double errMeyer = 0, errTaubin = 0;
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    errMeyer += std::abs(meyer.G[i] - 1);
    errTaubin += std::abs(tau.G[i] - 1);
    EXPECT_NEAR(tau.H[i], 1.0, 0.1); // a sane estimate, if a coarser one
    EXPECT_GE(tau.K1[i], tau.K2[i]);
  }
  EXPECT_LT(errMeyer, errTaubin);
}

// An irregular torus: parameters jittered by up to 10% of the cell size (the
// points stay on the torus).  The cotangent operators are not convergent on
// irregular meshes, so the bound is on the error level, and the thesis'
// operators must beat Taubin's tensor on the same mesh.
TEST(Curvatures, JitteredTorus)
{
  const double R = 1.0, r = 0.4;
  std::vector<std::array<double, 2>> uv;
  const Mesh m = test::Torus(R, r, 120, 60, 0.1, 7, &uv);
  CurvatureOptions taubin;
  taubin.Method = CurvatureMethod::Taubin1995;
  const Result res = Compute(m), tau = Compute(m, taubin);
  double errH = 0, errG = 0, tauH = 0, tauG = 0, maxG = 0;
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    const double c = std::cos(uv[i][1]);
    const double h = (1 / r + c / (R + r * c)) / 2, g = c / (r * (R + r * c));
    errH += std::abs(res.H[i] - h) / h;
    errG += std::abs(res.G[i] - g);
    tauH += std::abs(tau.H[i] - h) / h;
    tauG += std::abs(tau.G[i] - g);
    maxG = std::max(maxG, std::abs(g));
  }
  const double n = m.NumberOfVertices();
  errH /= n;
  tauH /= n;
  errG /= n * maxG;
  tauG /= n * maxG;
  std::printf("jittered torus: mean rel. error kappa_H %.3f%% (Taubin %.3f%%), kappa_G %.3f%% of "
              "max (Taubin %.3f%%)\n",
    100 * errH, 100 * tauH, 100 * errG, 100 * tauG);
  EXPECT_LT(errH, 0.03);
  EXPECT_LT(errG, 0.015);
  EXPECT_LT(5 * errH, tauH);
  EXPECT_LT(5 * errG, tauG);
}

namespace
{

struct Quadric
{
  double a, b; // z = a x^2 + b y^2
  // Analytic values for the +z orientation, in the filter's sign convention
  // (positive where the surface bends away from the normal).
  void Exact(double x, double y, double& h, double& g, double& k1, double& k2) const
  {
    const double fx = 2 * a * x, fy = 2 * b * y, fxx = 2 * a, fyy = 2 * b;
    const double w2 = 1 + fx * fx + fy * fy, w = std::sqrt(w2);
    const double hStd = ((1 + fy * fy) * fxx + (1 + fx * fx) * fyy) / (2 * w2 * w);
    g = fxx * fyy / (w2 * w2);
    h = -hStd;
    const double d = std::sqrt(std::max(0.0, h * h - g));
    k1 = h + d;
    k2 = h - d;
  }
};

void CheckQuadric(const Quadric& q, double jitter, bool randomDiagonals, double tolH,
  double tolG, const char* name)
{
  const Mesh m = test::HeightField(
    [&](double x, double y) { return q.a * x * x + q.b * y * y; }, 0.5, 81, jitter,
    randomDiagonals, 3);
  const Result r = Compute(m);
  double errH = 0, errG = 0, scale = 0;
  int count = 0;
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    if (r.Status[i] != 0)
    {
      EXPECT_TRUE(std::isnan(r.H[i])); // boundary: undefined
      continue;
    }
    const Eigen::Vector3d p = m.Point(i);
    double h, g, k1, k2;
    q.Exact(p.x(), p.y(), h, g, k1, k2);
    errH += std::abs(r.H[i] - h);
    errG += std::abs(r.G[i] - g);
    scale += std::abs(k1) + std::abs(k2);
    EXPECT_GE(r.K1[i], r.K2[i]);
    ++count;
  }
  scale /= 2 * count; // mean principal-curvature magnitude
  errH /= count * scale;
  errG /= count * scale * scale;
  std::printf("%-28s interior %5d: mean error kappa_H %.4f%%, kappa_G %.4f%% (relative)\n", name,
    count, 100 * errH, 100 * errG);
  EXPECT_LT(errH, tolH) << name;
  EXPECT_LT(errG, tolG) << name;
}

} // namespace

TEST(Curvatures, ParaboloidAndSaddleRegularGrid)
{
  CheckQuadric({ 1, 1 }, 0, false, 0.002, 0.005, "paraboloid (regular)");
  CheckQuadric({ 1, -1 }, 0, false, 0.002, 0.005, "saddle (regular)");
}

TEST(Curvatures, ParaboloidAndSaddleJitteredGrid)
{
  CheckQuadric({ 1, 1 }, 0.1, true, 0.05, 0.05, "paraboloid (jittered)");
  CheckQuadric({ 1, -1 }, 0.1, true, 0.05, 0.05, "saddle (jittered)");
}

TEST(Curvatures, SaddleSignsAndOrdering)
{
  const Mesh m = test::HeightField(
    [](double x, double y) { return x * x - y * y; }, 0.5, 41, 0.2, true, 11);
  const Result r = Compute(m);
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    if (r.Status[i] == 0)
    {
      EXPECT_GT(r.K1[i], 0) << i;
      EXPECT_LT(r.K2[i], 0) << i;
      EXPECT_LT(r.G[i], 0) << i;
    }
  }
}

// kappa_1 = 1/r with e1 around the circumference; kappa_2 = 0 with e2 along the axis.
TEST(Curvatures, CylinderOrderingAndDirections)
{
  const double radius = 0.5;
  const Mesh m = test::Cylinder(radius, 2.0, 64, 40);
  const Result r = Compute(m);
  int interior = 0;
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    if (r.Status[i] != 0)
    {
      EXPECT_EQ(r.Status[i], VertexBoundary);
      continue;
    }
    ++interior;
    const Eigen::Vector3d axis(0, 0, 1);
    EXPECT_NEAR(r.K1[i], 1 / radius, 0.01 / radius);
    EXPECT_NEAR(r.K2[i], 0.0, 0.01 / radius);
    EXPECT_NEAR(r.H[i], 0.5 / radius, 0.005 / radius);
    EXPECT_LT(std::abs(r.Vec(r.E1, i).dot(axis)), 0.02) << "e1 must go around";
    EXPECT_GT(std::abs(r.Vec(r.E2, i).dot(axis)), 0.999) << "e2 must follow the axis";
    const Eigen::Vector3d radial = Eigen::Vector3d(m.Point(i).x(), m.Point(i).y(), 0).normalized();
    EXPECT_GT(r.Vec(r.N, i).dot(radial), 0.999) << "outward normal";
  }
  EXPECT_GT(interior, 0);
}

// Principal directions on an ellipsoid against the analytic shape operator.
TEST(Curvatures, EllipsoidPrincipalDirections)
{
  const Eigen::Vector3d axes(1.5, 1.0, 0.6);
  Mesh m = test::OctahedronSphere(5);
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    m.SetPoint(i, m.Point(i).cwiseProduct(axes));
  }
  const Result r = Compute(m);
  double sumAngle = 0, maxAngle = 0, errK1 = 0, errK2 = 0;
  int count = 0;
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    const Eigen::Vector3d p = m.Point(i);
    const Eigen::Vector3d hess = (2.0 / axes.array().square()).matrix();
    const Eigen::Vector3d grad = hess.cwiseProduct(p);
    const Eigen::Vector3d n = grad.normalized();
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - n * n.transpose();
    const Eigen::Matrix3d S = P * hess.asDiagonal() * P / grad.norm();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(S);
    const double k1 = eig.eigenvalues()[2], k2 = eig.eigenvalues()[1];
    if (k1 - k2 < 0.1 * k1)
    {
      continue; // near an umbilic the direction is not defined
    }
    const Eigen::Vector3d d1 = eig.eigenvectors().col(2);
    const double angle = std::acos(std::min(1.0, std::abs(d1.dot(r.Vec(r.E1, i))))) * 180 / M_PI;
    sumAngle += angle;
    maxAngle = std::max(maxAngle, angle);
    ++count;
    errK1 += std::abs(r.K1[i] - k1) / k1;
    errK2 += std::abs(r.K2[i] - k2) / k2;
  }
  const double mean = sumAngle / count;
  errK1 /= count;
  errK2 /= count;
  std::printf("ellipsoid: %d non-umbilic vertices, e1 mean angular error %.3f deg, max %.3f deg; "
              "kappa_1 %.3f%%, kappa_2 %.3f%% mean rel. error\n",
    count, mean, maxAngle, 100 * errK1, 100 * errK2);
  EXPECT_GT(count, 1000);
  EXPECT_LT(mean, 1.5);
  EXPECT_LT(errK1, 0.01);
  EXPECT_LT(errK2, 0.01);
}

TEST(Curvatures, FramesAreOrthonormalAndOrdered)
{
  std::vector<std::array<double, 2>> uv;
  const Mesh m = test::Torus(1.0, 0.3, 50, 30, 0.3, 5, &uv);
  const Result r = Compute(m);
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    const Eigen::Vector3d e1 = r.Vec(r.E1, i), e2 = r.Vec(r.E2, i), n = r.Vec(r.N, i);
    EXPECT_NEAR(e1.norm(), 1, 1e-12);
    EXPECT_NEAR(e2.norm(), 1, 1e-12);
    EXPECT_NEAR(n.norm(), 1, 1e-12);
    EXPECT_NEAR(e1.dot(e2), 0, 1e-12);
    EXPECT_NEAR(e1.dot(n), 0, 1e-12);
    EXPECT_NEAR(e2.dot(n), 0, 1e-12);
    EXPECT_GE(r.K1[i], r.K2[i]);
  }
}

// Sum of kappa_G * A_Mixed = 2 pi chi on closed meshes (genus 0 and 1 here;
// genus 2 on a real mesh in the VTK-level tests).
TEST(Curvatures, GaussBonnet)
{
  struct Case
  {
    Mesh M;
    int Chi;
  };
  const Case cases[] = { { test::OctahedronSphere(4), 2 }, { test::Torus(1, 0.3, 40, 17, 0.3, 9), 0 } };
  for (const Case& c : cases)
  {
    const Result r = Compute(c.M);
    EXPECT_EQ(c.M.Topology().Summary().EulerCharacteristic, c.Chi);
    double total = 0;
    for (Index i = 0; i < c.M.NumberOfVertices(); ++i)
    {
      total += r.G[i] * r.A[i];
    }
    EXPECT_NEAR(total, 2 * M_PI * c.Chi, 1e-9);
  }
}

// Edges collapsed in place (one end moved onto the other, as decimations
// and marching cubes at grid points leave them): the zero-area triangles'
// angles still count, the two coincident corners sharing pi, so the total
// curvature stays 2 pi chi (with an angle of 0 at each, 4 pi plus pi per
// such triangle).
TEST(Curvatures, GaussBonnetHoldsWithCollapsedEdges)
{
  Mesh m = test::OctahedronSphere(4);
  std::vector<std::uint8_t> used(static_cast<std::size_t>(m.NumberOfVertices()), 0);
  int collapsed = 0;
  for (std::size_t t = 0; t < m.Triangles.size(); t += 3 * 7)
  {
    const Index a = m.Triangles[t], c = m.Triangles[t + 1];
    if (!used[a] && !used[c])
    {
      used[a] = used[c] = 1;
      for (int k = 0; k < 3; ++k)
      {
        m.Points[3 * c + k] = m.Points[3 * a + k];
      }
      ++collapsed;
    }
  }
  ASSERT_GT(collapsed, 10);
  const Result r = Compute(m);
  double total = 0;
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    total += r.G[i] * r.A[i];
  }
  EXPECT_NEAR(total, 4 * M_PI, 1e-9);
}

TEST(Curvatures, FlatTriangulationsHaveZeroCurvature)
{
  for (unsigned seed : { 1u, 2u, 3u })
  {
    const Mesh m = test::FlatIrregular(25, seed);
    const Result r = Compute(m);
    int interior = 0, obtuse = 0;
    for (std::size_t t = 0; t < m.Triangles.size(); t += 3)
    {
      for (int k = 0; k < 3; ++k)
      {
        const Eigen::Vector3d a = m.Point(m.Triangles[t + k]);
        const Eigen::Vector3d b = m.Point(m.Triangles[t + (k + 1) % 3]);
        const Eigen::Vector3d c = m.Point(m.Triangles[t + (k + 2) % 3]);
        obtuse += (b - a).dot(c - a) < 0;
      }
    }
    for (Index i = 0; i < m.NumberOfVertices(); ++i)
    {
      if (r.Status[i] != 0)
      {
        continue;
      }
      ++interior;
      EXPECT_LT(r.Vec(r.K, i).norm(), 1e-9);
      EXPECT_LT(std::abs(r.G[i]), 1e-9);
      EXPECT_LT(std::abs(r.K1[i]), 1e-4); // sqrt of round-off
      EXPECT_NEAR(std::abs(r.Vec(r.N, i).z()), 1.0, 1e-12);
    }
    EXPECT_GT(obtuse, 100);
    EXPECT_GT(interior, 500);
  }
}

TEST(Curvatures, MixedAreasTileTheSurface)
{
  const Mesh meshes[] = { test::FlatIrregular(20, 4), test::Torus(1, 0.3, 30, 12, 0.4, 2),
    test::HeightField([](double x, double y) { return x * y; }, 1, 20, 0.3, true, 8) };
  for (const Mesh& m : meshes)
  {
    const Result r = Compute(m);
    EXPECT_NEAR(Sum(r.A), m.TotalArea(), 1e-12 * m.TotalArea());
  }
}

TEST(Curvatures, InvariantUnderRigidMotion)
{
  const Mesh m = test::Torus(1, 0.35, 40, 20, 0.3, 12);
  Mesh moved = m;
  const Eigen::Matrix3d Q =
    Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Vector3d shift(10, -3, 5);
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    moved.SetPoint(i, Q * m.Point(i) + shift);
  }
  const Result a = Compute(m), b = Compute(moved);
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    EXPECT_NEAR(a.H[i], b.H[i], 1e-9);
    EXPECT_NEAR(a.G[i], b.G[i], 1e-9);
    EXPECT_NEAR(a.K1[i], b.K1[i], 1e-9);
    EXPECT_NEAR(a.A[i], b.A[i], 1e-12);
    EXPECT_LT((Q * a.Vec(a.K, i) - b.Vec(b.K, i)).norm(), 1e-9);
    EXPECT_LT((Q * a.Vec(a.N, i) - b.Vec(b.N, i)).norm(), 1e-9);
    EXPECT_GT(std::abs((Q * a.Vec(a.E1, i)).dot(b.Vec(b.E1, i))), 1 - 1e-6);
  }
}

TEST(Curvatures, ThreadCountDoesNotChangeResults)
{
  const Mesh m = test::Torus(1, 0.35, 200, 80, 0.3, 13);
  CurvatureOptions one, many;
  one.NumberOfThreads = 1;
  many.NumberOfThreads = 4;
  const Result a = Compute(m, one), b = Compute(m, many);
  EXPECT_EQ(a.H, b.H);
  EXPECT_EQ(a.E1, b.E1);
  EXPECT_EQ(a.Status, b.Status);
}

// The crease measure of the line drawing, read off the 1-ring loop: at each
// vertex of a closed, consistently oriented fan the smallest cosine between
// the normals of two triangles that share an edge there, as a brute-force
// edge map gives it; NaN at boundary vertices (the caller's to fill).
TEST(Curvatures, SharpestEdgeCosineOfRegularFans)
{
  const Mesh meshes[] = { test::OctahedronSphere(0), test::CubeSurface(4), test::Torus(1, 0.3, 30, 12, 0.4, 2),
    test::FlatIrregular(12, 5) }; // (the last one has a boundary)
  for (const Mesh& m : meshes)
  {
    const bool open = &m == &meshes[3];
    std::map<std::pair<Index, Index>, std::vector<Eigen::Vector3d>> edges; // the normals of each edge's faces
    for (std::size_t t = 0; t < m.Triangles.size(); t += 3)
    {
      const Eigen::Vector3d a = m.Point(m.Triangles[t]);
      const Eigen::Vector3d n = (m.Point(m.Triangles[t + 1]) - a).cross(m.Point(m.Triangles[t + 2]) - a).normalized();
      for (int k = 0; k < 3; ++k)
      {
        const Index i = m.Triangles[t + k], j = m.Triangles[t + (k + 1) % 3];
        edges[{ std::min(i, j), std::max(i, j) }].push_back(n);
      }
    }
    std::vector<double> expected(m.NumberOfVertices(), 1.0);
    std::vector<bool> boundary(m.NumberOfVertices(), false);
    for (const auto& [ends, normals] : edges)
    {
      for (Index v : { ends.first, ends.second })
      {
        if (normals.size() == 2)
        {
          expected[v] = std::min(expected[v], normals[0].dot(normals[1]));
        }
        else
        {
          boundary[v] = true;
        }
      }
    }
    const MeshTopology topo = m.Topology();
    std::vector<float> sharpest(m.NumberOfVertices(), -2.0f);
    CurvatureOutputs out;
    out.SharpestEdgeCosine = sharpest.data();
    ComputeCurvatures(topo, m.Points.data(), {}, out);
    int boundaryVertices = 0;
    for (Index i = 0; i < m.NumberOfVertices(); ++i)
    {
      boundaryVertices += boundary[i];
      if (boundary[i])
      {
        EXPECT_TRUE(std::isnan(sharpest[i])) << i;
      }
      else
      {
        EXPECT_NEAR(sharpest[i], expected[i], 1e-6) << i;
      }
    }
    EXPECT_EQ(boundaryVertices > 0, open);
  }
  // The octahedron's edges: cosine 1/3, known without the map.
  const Mesh octahedron = test::OctahedronSphere(0);
  std::vector<float> sharpest(octahedron.NumberOfVertices());
  CurvatureOutputs out;
  out.SharpestEdgeCosine = sharpest.data();
  ComputeCurvatures(octahedron.Topology(), octahedron.Points.data(), {}, out);
  for (float c : sharpest)
  {
    EXPECT_NEAR(c, 1.0 / 3.0, 1e-7);
  }
}

TEST(Curvatures, FloatAndDoublePointsAgree)
{
  const Mesh m = test::OctahedronSphere(4);
  const std::vector<float> pf(m.Points.begin(), m.Points.end());
  const MeshTopology topo = m.Topology();
  std::vector<double> hf(m.NumberOfVertices()), hd(m.NumberOfVertices());
  CurvatureOutputs of, od;
  of.MeanCurvature = hf.data();
  od.MeanCurvature = hd.data();
  ComputeCurvatures(topo, pf.data(), {}, of);
  ComputeCurvatures(topo, m.Points.data(), {}, od);
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    EXPECT_NEAR(hf[i], hd[i], 1e-3);
  }
}

TEST(Curvatures, NormalWeightingsOnASphere)
{
  const Mesh m = test::OctahedronSphere(3);
  for (auto w : { NormalWeighting::MeanCurvatureNormal, NormalWeighting::Uniform,
         NormalWeighting::Angle, NormalWeighting::Max1999, NormalWeighting::Area })
  {
    CurvatureOptions o;
    o.Weighting = w;
    const Result r = Compute(m, o);
    double worst = 1;
    for (Index i = 0; i < m.NumberOfVertices(); ++i)
    {
      worst = std::min(worst, r.Vec(r.N, i).dot(m.Point(i).normalized()));
    }
    EXPECT_GT(worst, 0.995) << static_cast<int>(w);
    if (w == NormalWeighting::Max1999)
    {
      EXPECT_GT(worst, 1 - 1e-12); // exact on any sphere tessellation
    }
  }
}

TEST(Curvatures, BoundaryPolicies)
{
  const Mesh m = test::HeightField(
    [](double x, double y) { return 0.5 * (x * x + y * y); }, 0.5, 21, 0, false, 1);
  CurvatureOptions average;
  average.Boundary = BoundaryPolicy::InteriorAverage;
  const Result nan = Compute(m), avg = Compute(m, average);
  int boundary = 0;
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    if (nan.Status[i] & VertexBoundary)
    {
      ++boundary;
      EXPECT_TRUE(std::isnan(nan.H[i]) && std::isnan(nan.G[i]) && std::isnan(nan.K1[i]));
      EXPECT_TRUE(std::isfinite(avg.H[i]) && std::isfinite(avg.K2[i]));
      // The bowl bends towards its +z normal: kappa_H < 0, near the analytic value.
      const double fx = m.Point(i).x(), fy = m.Point(i).y(), w2 = 1 + fx * fx + fy * fy;
      const double exact = -(2 + fx * fx + fy * fy) / (2 * w2 * std::sqrt(w2));
      EXPECT_NEAR(avg.H[i], exact, 0.1 * std::abs(exact));
      EXPECT_TRUE(std::isnan(avg.E1[3 * i]));
      EXPECT_GT(nan.A[i], 0);                       // areas and normals stay defined
      EXPECT_GT(nan.Vec(nan.N, i).z(), 0.5);
    }
    else
    {
      EXPECT_EQ(nan.H[i], avg.H[i]);
    }
  }
  EXPECT_EQ(boundary, 80);
}

// Interior-average filling must not overwrite vertices whose values exist,
// such as an interior vertex next to an inconsistently oriented triangle.
TEST(Curvatures, InteriorAverageKeepsComputedValues)
{
  Mesh m = test::HeightField(
    [](double x, double y) { return 0.5 * (x * x + y * y); }, 0.5, 15, 0, false, 1);
  std::swap(m.Triangles[3 * 100], m.Triangles[3 * 100 + 1]); // flip one interior triangle
  CurvatureOptions average;
  average.Boundary = BoundaryPolicy::InteriorAverage;
  const Result nan = Compute(m), avg = Compute(m, average);
  int inconsistent = 0;
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    if (nan.Status[i] == VertexInconsistent)
    {
      ++inconsistent;
      EXPECT_TRUE(std::isfinite(nan.G[i]));
      EXPECT_EQ(avg.G[i], nan.G[i]);
      EXPECT_EQ(avg.K1[i], nan.K1[i]);
    }
  }
  EXPECT_EQ(inconsistent, 3);
}

// Section 2.8.1: the same operator for a surface embedded in R^5.
TEST(SurfaceOperators, BeltramiInHigherDimensions)
{
  const Mesh m = test::Torus(1, 0.4, 30, 15, 0.3, 21);
  const Index n = m.NumberOfVertices();
  const MeshTopology topo = m.Topology();
  // An isometric embedding R^3 -> R^5 (orthonormal columns).
  Eigen::Matrix<double, 5, 5> rnd = Eigen::Matrix<double, 5, 5>::Random();
  const Eigen::Matrix<double, 5, 3> frame =
    Eigen::HouseholderQR<Eigen::Matrix<double, 5, 5>>(rnd).householderQ() *
    Eigen::Matrix<double, 5, 3>::Identity();
  std::vector<double> p5(5 * n);
  for (Index i = 0; i < n; ++i)
  {
    Eigen::Map<Eigen::Matrix<double, 5, 1>> dst(&p5[5 * i]);
    dst = frame * m.Point(i) + Eigen::Matrix<double, 5, 1>::Constant(2.0);
  }
  std::vector<double> k3(3 * n), a3(n), d3(n), k5(5 * n), a5(n), d5(n);
  ComputeBeltramiOperator(topo, m.Points.data(), 3, 3, k3.data(), a3.data(), d3.data());
  ComputeBeltramiOperator(topo, p5.data(), 5, 5, k5.data(), a5.data(), d5.data());
  for (Index i = 0; i < n; ++i)
  {
    const Eigen::Matrix<double, 5, 1> expected = frame * Eigen::Vector3d(k3[3 * i], k3[3 * i + 1], k3[3 * i + 2]);
    EXPECT_LT((Eigen::Map<Eigen::Matrix<double, 5, 1>>(&k5[5 * i]) - expected).norm(), 1e-9);
    EXPECT_NEAR(a3[i], a5[i], 1e-12);
    EXPECT_NEAR(d3[i], d5[i], 1e-12);
  }
  // The curvature filter's K is this operator.
  const Result r = Compute(m);
  for (Index i = 0; i < n; ++i)
  {
    EXPECT_LT((r.Vec(r.K, i) - Eigen::Vector3d(k3[3 * i], k3[3 * i + 1], k3[3 * i + 2])).norm(), 1e-12);
  }
}
