// The helper process of vtkTetGenTetrahedralizer: TetGen (libtet 1.5) runs
// here, because libtet frees its memory twice when it throws on a
// self-intersecting or nearly touching surface; a crash of this process is
// an error message in the filter, not a crash of ParaView.
//
// Standard input (little-endian): "BTET1", the switches (uint32 length +
// characters), the number of points (int32) and their coordinates (3
// doubles each), the number of triangles (int32) and their point ids (3
// int32 each).  Standard output: "BTET1", a status (int32: 0, or TetGen's
// error code with a message), then the points (int32 count, 3 doubles each)
// and the tetrahedra (int32 count, 4 int32 each).  With the argument
// --intersections it runs TetGen's self-intersection check (pdQz) on the
// surface instead and answers "BTET1", 0 and the number of intersecting
// triangles (int32): the diagnosis after a crash.
#define TETLIBRARY // Debian's libtet is built with it: errors are thrown, not exit()
#include <tetgen.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <new>
#include <string>
#include <unistd.h>
#include <vector>

namespace
{

bool ReadAll(void* out, std::size_t n)
{
  char* p = static_cast<char*>(out);
  while (n > 0)
  {
    const ssize_t r = read(0, p, n);
    if (r <= 0)
    {
      return false;
    }
    p += r;
    n -= static_cast<std::size_t>(r);
  }
  return true;
}

void WriteAll(const void* data, std::size_t n)
{
  const char* p = static_cast<const char*>(data);
  while (n > 0)
  {
    const ssize_t w = write(1, p, n);
    if (w <= 0)
    {
      _exit(3);
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
}

template <typename T>
void Put(T v)
{
  WriteAll(&v, sizeof(T));
}

int Fail(std::int32_t code, const std::string& message)
{
  WriteAll("BTET1", 5);
  Put<std::int32_t>(code);
  Put<std::uint32_t>(static_cast<std::uint32_t>(message.size()));
  WriteAll(message.data(), message.size());
  return 0;
}

} // namespace

int main(int argc, char* argv[])
{
  const bool intersections = argc > 1 && std::strcmp(argv[1], "--intersections") == 0;
  char magic[5];
  std::uint32_t length = 0;
  if (!ReadAll(magic, 5) || std::memcmp(magic, "BTET1", 5) != 0 || !ReadAll(&length, 4) || length > 256)
  {
    return Fail(10, "malformed request");
  }
  std::vector<char> switches(length + 1, '\0');
  std::int32_t numPoints = 0, numTriangles = 0;
  if (!ReadAll(switches.data(), length) || !ReadAll(&numPoints, 4) || numPoints < 4 ||
    numPoints > (1 << 28))
  {
    return Fail(10, "malformed request");
  }
  tetgenio in, out;
  in.firstnumber = 0;
  in.numberofpoints = numPoints;
  in.pointlist = new REAL[3 * static_cast<std::size_t>(numPoints)];
  if (!ReadAll(in.pointlist, 3 * sizeof(double) * static_cast<std::size_t>(numPoints)) ||
    !ReadAll(&numTriangles, 4) || numTriangles < 4 || numTriangles > (1 << 28))
  {
    return Fail(10, "malformed request");
  }
  std::vector<std::int32_t> triangles(3 * static_cast<std::size_t>(numTriangles));
  if (!ReadAll(triangles.data(), triangles.size() * sizeof(std::int32_t)))
  {
    return Fail(10, "malformed request");
  }
  in.numberoffacets = numTriangles;
  in.facetlist = new tetgenio::facet[numTriangles];
  for (std::int32_t f = 0; f < numTriangles; ++f)
  {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k)
    {
      const std::int32_t id = triangles[3 * static_cast<std::size_t>(f) + k];
      if (id < 0 || id >= numPoints)
      {
        return Fail(10, "a triangle refers to a point that does not exist");
      }
      facet.polygonlist[0].vertexlist[k] = id;
    }
  }
  char check[] = "pdQz";
  try
  {
    tetrahedralize(intersections ? check : switches.data(), &in, &out);
  }
  catch (int code)
  {
    std::fflush(stdout);
    return Fail(code, "TetGen failed");
  }
  catch (const std::bad_alloc&)
  {
    return Fail(1, "TetGen ran out of memory");
  }
  if (intersections)
  {
    WriteAll("BTET1", 5);
    Put<std::int32_t>(0);
    Put<std::int32_t>(out.numberoftrifaces);
    return 0;
  }
  if (out.numberoftetrahedra <= 0 || out.numberofpoints <= 0 || out.numberofcorners < 4)
  {
    return Fail(20, "TetGen produced no tetrahedra");
  }
  WriteAll("BTET1", 5);
  Put<std::int32_t>(0);
  Put<std::int32_t>(out.numberofpoints);
  WriteAll(out.pointlist, 3 * sizeof(double) * static_cast<std::size_t>(out.numberofpoints));
  Put<std::int32_t>(out.numberoftetrahedra);
  std::vector<std::int32_t> tets(4 * static_cast<std::size_t>(out.numberoftetrahedra));
  for (int t = 0; t < out.numberoftetrahedra; ++t)
  {
    for (int k = 0; k < 4; ++k)
    {
      tets[4 * static_cast<std::size_t>(t) + k] = out.tetrahedronlist[t * out.numberofcorners + k];
    }
  }
  WriteAll(tets.data(), tets.size() * sizeof(std::int32_t));
  return 0;
}
