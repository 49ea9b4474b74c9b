#include "Flows/ColorSpace.h"

#include <algorithm>
#include <cmath>

namespace beltrami
{

namespace
{

// sRGB primaries, D65 white (IEC 61966-2-1), and the exact inverse.
constexpr double RGBToXYZ[3][3] = { { 0.4124564, 0.3575761, 0.1804375 },
  { 0.2126729, 0.7151522, 0.0721750 }, { 0.0193339, 0.1191920, 0.9503041 } };

struct Inverse3
{
  double M[3][3];
  Inverse3()
  {
    const auto& a = RGBToXYZ;
    const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
      a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
        M[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
      }
    }
  }
};
const Inverse3 XYZToRGB;

// White point (Y = 1) and its chromaticity.
const double Xn = RGBToXYZ[0][0] + RGBToXYZ[0][1] + RGBToXYZ[0][2];
const double Zn = RGBToXYZ[2][0] + RGBToXYZ[2][1] + RGBToXYZ[2][2];
const double Un = 4.0 * Xn / (Xn + 15.0 + 3.0 * Zn);
const double Vn = 9.0 / (Xn + 15.0 + 3.0 * Zn);
constexpr double Epsilon = 216.0 / 24389.0; // (6/29)^3
constexpr double Kappa = 24389.0 / 27.0;    // (29/3)^3

double ToLinear(double c)
{
  c = std::min(1.0, std::max(0.0, c));
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

double FromLinear(double l)
{
  l = std::min(1.0, std::max(0.0, l));
  return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
}

void ForEachColor(double* colors, std::int64_t count, int stride, int threads, void (*convert)(double*))
{
  ParallelFor(count, threads, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i)
    {
      convert(colors + i * stride);
    }
  });
}

void ToLuv(double* c)
{
  const double rgb[3] = { ToLinear(c[0]), ToLinear(c[1]), ToLinear(c[2]) };
  double xyz[3];
  for (int i = 0; i < 3; ++i)
  {
    xyz[i] = RGBToXYZ[i][0] * rgb[0] + RGBToXYZ[i][1] * rgb[1] + RGBToXYZ[i][2] * rgb[2];
  }
  const double y = xyz[1];
  const double L = y > Epsilon ? 116.0 * std::cbrt(y) - 16.0 : Kappa * y;
  const double denominator = xyz[0] + 15.0 * xyz[1] + 3.0 * xyz[2];
  double u = 0.0, v = 0.0;
  if (denominator > 0.0)
  {
    u = 13.0 * L * (4.0 * xyz[0] / denominator - Un);
    v = 13.0 * L * (9.0 * xyz[1] / denominator - Vn);
  }
  c[0] = L / 100.0;
  c[1] = u / 100.0;
  c[2] = v / 100.0;
}

void FromLuv(double* c)
{
  const double L = 100.0 * c[0], u = 100.0 * c[1], v = 100.0 * c[2];
  double xyz[3] = { 0.0, 0.0, 0.0 };
  if (L > 1e-12)
  {
    const double y = L > Kappa * Epsilon ? std::pow((L + 16.0) / 116.0, 3.0) : L / Kappa;
    const double up = u / (13.0 * L) + Un, vp = v / (13.0 * L) + Vn;
    if (vp > 1e-12)
    {
      xyz[0] = y * 9.0 * up / (4.0 * vp);
      xyz[1] = y;
      xyz[2] = y * (12.0 - 3.0 * up - 20.0 * vp) / (4.0 * vp);
    }
  }
  for (int i = 0; i < 3; ++i)
  {
    const auto& m = XYZToRGB.M[i];
    c[i] = FromLinear(m[0] * xyz[0] + m[1] * xyz[1] + m[2] * xyz[2]);
  }
}

} // namespace

void RGBToLuv(double* colors, std::int64_t count, int stride, int numThreads)
{
  ForEachColor(colors, count, stride, numThreads, &ToLuv);
}

void LuvToRGB(double* colors, std::int64_t count, int stride, int numThreads)
{
  ForEachColor(colors, count, stride, numThreads, &FromLuv);
}

} // namespace beltrami
