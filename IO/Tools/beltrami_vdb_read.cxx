// beltrami-vdb-read FILE GRID MAXVOXELS [active]
//
// Parses an OpenVDB file in a process of its own for vtkOpenVDBReader:
// OpenVDB's parser can corrupt the heap on damaged files, so it never runs
// inside ParaView or Python.  Writes to stdout (binary, native endianness):
//   "BVDB1", int32 status (0 ok, 1 error); on error: uint32 length, message;
//   on success: uint32 number of grids, each as uint32 length + name; the
//   selected grid's name likewise; int32 components (1, 3), int32 double (0,
//   1), int32 extent[6], double origin[3], double spacing[3], int64 active
//   voxel count; then the values over the extent, x fastest.  With "active":
//   instead of the values over the extent, the active voxels only (the grid
//   is never densified): int64 count, count x int32 (i, j, k), then their
//   values in the same order.
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace
{
void Put(const void* p, std::size_t n)
{
  if (std::fwrite(p, 1, n, stdout) != n)
  {
    std::exit(3);
  }
}
template <typename T>
void Put(T v)
{
  Put(&v, sizeof(T));
}
void PutString(const std::string& s)
{
  Put(static_cast<std::uint32_t>(s.size()));
  Put(s.data(), s.size());
}

template <typename GridT, typename S>
void PutValues(const openvdb::GridBase& base, const int* ext, int nc)
{
  const GridT& grid = static_cast<const GridT&>(base);
  auto accessor = grid.getConstAccessor();
  std::vector<S> row;
  for (int k = ext[4]; k <= ext[5]; ++k)
  {
    for (int j = ext[2]; j <= ext[3]; ++j)
    {
      row.clear();
      for (int i = ext[0]; i <= ext[1]; ++i)
      {
        const auto v = accessor.getValue(openvdb::Coord(i, j, k));
        if constexpr (std::is_arithmetic_v<std::decay_t<decltype(v)>>)
        {
          row.push_back(static_cast<S>(v));
        }
        else
        {
          for (int c = 0; c < nc; ++c)
          {
            row.push_back(static_cast<S>(v[c]));
          }
        }
      }
      Put(row.data(), row.size() * sizeof(S));
    }
  }
}

template <typename GridT, typename S>
void PutActive(const openvdb::GridBase& base, int nc)
{
  const GridT& grid = static_cast<const GridT&>(base);
  std::vector<std::int32_t> ijk;
  std::vector<S> values;
  for (auto it = grid.cbeginValueOn(); it; ++it)
  {
    // Tile values (whole active blocks stored as one value) are expanded.
    const openvdb::CoordBBox box = it.getBoundingBox();
    for (auto c = box.begin(); c; ++c)
    {
      const openvdb::Coord xyz = *c;
      ijk.insert(ijk.end(), { xyz[0], xyz[1], xyz[2] });
      const auto v = *it;
      if constexpr (std::is_arithmetic_v<std::decay_t<decltype(v)>>)
      {
        values.push_back(static_cast<S>(v));
      }
      else
      {
        for (int k = 0; k < nc; ++k)
        {
          values.push_back(static_cast<S>(v[k]));
        }
      }
    }
  }
  Put(static_cast<std::int64_t>(ijk.size() / 3));
  Put(ijk.data(), ijk.size() * sizeof(std::int32_t));
  Put(values.data(), values.size() * sizeof(S));
}

int Fail(const std::string& message)
{
  Put(static_cast<std::int32_t>(1));
  PutString(message);
  return 0;
}
} // namespace

int main(int argc, char** argv)
{
  Put("BVDB1", 5);
  if (argc < 4)
  {
    return Fail("usage: beltrami-vdb-read FILE GRID MAXVOXELS");
  }
  const std::string gridName = argv[2];
  const double maximumVoxels = std::atof(argv[3]);
  const bool activeOnly = argc > 4 && std::string(argv[4]) == "active";
  try
  {
    openvdb::initialize();
    std::ifstream in(argv[1], std::ios::binary);
    if (!in)
    {
      return Fail("cannot open the file");
    }
    std::ostringstream bytes;
    bytes << in.rdbuf();
    // A stream that throws at its end: a truncated file must not make the
    // parser loop.
    std::istringstream is(bytes.str());
    is.exceptions(std::ios::failbit | std::ios::badbit | std::ios::eofbit);
    openvdb::io::Stream stream(is, /*delayLoad=*/false);
    const openvdb::GridPtrVecPtr grids = stream.getGrids();
    openvdb::GridBase::Ptr grid;
    for (const auto& g : *grids)
    {
      if (g && !grid && (gridName.empty() || g->getName() == gridName))
      {
        grid = g;
      }
    }
    if (!grid)
    {
      return Fail(gridName.empty() ? "the file has no grid" : "the file has no grid named '" + gridName + "'");
    }
    const std::string type = grid->valueType();
    const int nc = type == "float" || type == "double" ? 1 : (type == "vec3s" || type == "vec3d" ? 3 : 0);
    if (nc == 0)
    {
      return Fail("grids of type '" + type + "' are not supported (float, double, vec3s, vec3d)");
    }
    const bool dbl = type == "double" || type == "vec3d";
    const openvdb::math::Transform& t = grid->transform();
    if (!t.isLinear())
    {
      return Fail("the grid's transform is not linear (frustum)");
    }
    double origin[3], spacing[3];
    const openvdb::Vec3d o = t.indexToWorld(openvdb::Vec3d(0, 0, 0));
    for (int a = 0; a < 3; ++a)
    {
      openvdb::Vec3d unit(0, 0, 0);
      unit[a] = 1;
      const openvdb::Vec3d axis = t.indexToWorld(unit) - o;
      for (int b = 0; b < 3; ++b)
      {
        if (b != a && std::abs(axis[b]) > 1e-12 * axis.length())
        {
          return Fail("the grid's transform is rotated or sheared (not an axis-aligned image)");
        }
      }
      if (!(axis[a] > 0.0) || !std::isfinite(axis[a]) || !std::isfinite(o[a]))
      {
        return Fail("the grid's voxel size is not positive and finite");
      }
      spacing[a] = axis[a];
      origin[a] = o[a];
    }
    int ext[6] = { 0, -1, 0, -1, 0, -1 };
    const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
    if (!box.empty())
    {
      double voxels = 1.0;
      for (int a = 0; a < 3; ++a)
      {
        ext[2 * a] = box.min()[a];
        ext[2 * a + 1] = box.max()[a];
        voxels *= static_cast<double>(box.max()[a]) - box.min()[a] + 1.0;
      }
      if (voxels > maximumVoxels && !activeOnly)
      {
        std::ostringstream s;
        s << "the active bounding box has " << voxels << " voxels, more than MaximumNumberOfVoxels ("
          << maximumVoxels << ")";
        return Fail(s.str());
      }
    }
    if (activeOnly && static_cast<double>(grid->activeVoxelCount()) > maximumVoxels)
    {
      std::ostringstream s;
      s << "the grid has " << grid->activeVoxelCount() << " active voxels, more than MaximumNumberOfVoxels ("
        << maximumVoxels << ")";
      return Fail(s.str());
    }
    Put(static_cast<std::int32_t>(0));
    Put(static_cast<std::uint32_t>(grids->size()));
    for (const auto& g : *grids)
    {
      PutString(g ? g->getName() : std::string());
    }
    PutString(grid->getName());
    Put(static_cast<std::int32_t>(nc));
    Put(static_cast<std::int32_t>(dbl));
    for (int e : ext)
    {
      Put(static_cast<std::int32_t>(e));
    }
    Put(origin, sizeof(origin));
    Put(spacing, sizeof(spacing));
    Put(static_cast<std::int64_t>(grid->activeVoxelCount()));
    if (activeOnly)
    {
      if (type == "float")
        PutActive<openvdb::FloatGrid, float>(*grid, 1);
      else if (type == "double")
        PutActive<openvdb::DoubleGrid, double>(*grid, 1);
      else if (type == "vec3s")
        PutActive<openvdb::Vec3SGrid, float>(*grid, 3);
      else
        PutActive<openvdb::Vec3DGrid, double>(*grid, 3);
    }
    else if (!box.empty())
    {
      if (type == "float")
        PutValues<openvdb::FloatGrid, float>(*grid, ext, 1);
      else if (type == "double")
        PutValues<openvdb::DoubleGrid, double>(*grid, ext, 1);
      else if (type == "vec3s")
        PutValues<openvdb::Vec3SGrid, float>(*grid, ext, 3);
      else
        PutValues<openvdb::Vec3DGrid, double>(*grid, ext, 3);
    }
    std::fflush(stdout);
  }
  catch (const std::exception& e)
  {
    return Fail(e.what());
  }
  return 0;
}
