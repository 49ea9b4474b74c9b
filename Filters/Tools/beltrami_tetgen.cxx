// The helper process of vtkTetGenTetrahedralizer: TetGen (libtet 1.5) runs
// here, because libtet frees its memory twice when it throws on a
// self-intersecting or nearly touching surface; a crash of this process is
// an error message in the filter, not a crash of ParaView.
//
// A request (little-endian): "BTET1", the switches (uint32 length +
// characters), the number of points (int32) and their coordinates (3
// doubles each), the number of triangles (int32) and their point ids (3
// int32 each), the number of hole points (int32: one inside each cavity)
// and their coordinates (3 doubles each).  The answer: "BTET1", a status
// (int32: 0, or TetGen's error code followed by a message), then the
// points (int32 count, 3 doubles each) and the tetrahedra (int32 count, 4
// int32 each).
//
//   beltrami-tetgen                  one request on stdin, its answer on stdout
//   beltrami-tetgen --serve          requests and answers as frames (uint64
//                                    length + bytes) until stdin ends
//                                    (PersistentHelperProcess: the heap stays warm)
//   beltrami-tetgen --intersections  one request: TetGen's self-intersection
//                                    check (pdQz) instead; answers "BTET1", 0
//                                    and the number of intersecting triangles
//                                    (int32): the diagnosis after a crash
#define TETLIBRARY // Debian's libtet is built with it: errors are thrown, not exit()
#include <tetgen.h>

#include <cstdint>
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

/// Reads a request from memory, never past its end.
class Request
{
public:
  Request(const std::vector<char>& bytes)
    : Bytes(bytes)
  {
  }
  bool Take(void* out, std::size_t n)
  {
    if (n > Bytes.size() - Position)
    {
      return false;
    }
    std::memcpy(out, Bytes.data() + Position, n);
    Position += n;
    return true;
  }

private:
  const std::vector<char>& Bytes;
  std::size_t Position = 0;
};

class Answer
{
public:
  std::vector<char> Bytes;
  void Put(const void* data, std::size_t n)
  {
    Bytes.insert(Bytes.end(), static_cast<const char*>(data), static_cast<const char*>(data) + n);
  }
  template <typename T>
  void Put(T v)
  {
    Put(&v, sizeof(T));
  }
  void Fail(std::int32_t code, const std::string& message)
  {
    Bytes.clear();
    Put("BTET1", 5);
    Put<std::int32_t>(code);
    Put<std::uint32_t>(static_cast<std::uint32_t>(message.size()));
    Put(message.data(), message.size());
  }
};

Answer Process(const std::vector<char>& bytes, bool intersections)
{
  Answer answer;
  Request request(bytes);
  char magic[5];
  std::uint32_t length = 0;
  if (!request.Take(magic, 5) || std::memcmp(magic, "BTET1", 5) != 0 || !request.Take(&length, 4) || length > 256)
  {
    answer.Fail(10, "malformed request");
    return answer;
  }
  std::vector<char> switches(length + 1, '\0');
  std::int32_t numPoints = 0, numTriangles = 0;
  if (!request.Take(switches.data(), length) || !request.Take(&numPoints, 4) || numPoints < 4 ||
    numPoints > (1 << 28))
  {
    answer.Fail(10, "malformed request");
    return answer;
  }
  tetgenio in, out;
  in.firstnumber = 0;
  in.numberofpoints = numPoints;
  in.pointlist = new REAL[3 * static_cast<std::size_t>(numPoints)];
  if (!request.Take(in.pointlist, 3 * sizeof(double) * static_cast<std::size_t>(numPoints)) ||
    !request.Take(&numTriangles, 4) || numTriangles < 4 || numTriangles > (1 << 28))
  {
    answer.Fail(10, "malformed request");
    return answer;
  }
  std::vector<std::int32_t> triangles(3 * static_cast<std::size_t>(numTriangles));
  if (!request.Take(triangles.data(), triangles.size() * sizeof(std::int32_t)))
  {
    answer.Fail(10, "malformed request");
    return answer;
  }
  std::int32_t numHoles = 0;
  if (!request.Take(&numHoles, 4) || numHoles < 0 || numHoles > numTriangles)
  {
    answer.Fail(10, "malformed request");
    return answer;
  }
  in.numberofholes = numHoles;
  in.holelist = new REAL[3 * static_cast<std::size_t>(numHoles) + 1];
  if (!request.Take(in.holelist, 3 * sizeof(double) * static_cast<std::size_t>(numHoles)))
  {
    answer.Fail(10, "malformed request");
    return answer;
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
        answer.Fail(10, "a triangle refers to a point that does not exist");
        return answer;
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
    answer.Fail(code, "TetGen failed");
    return answer;
  }
  catch (const std::bad_alloc&)
  {
    answer.Fail(1, "TetGen ran out of memory");
    return answer;
  }
  answer.Put("BTET1", 5);
  answer.Put<std::int32_t>(0);
  if (intersections)
  {
    answer.Put<std::int32_t>(out.numberoftrifaces);
    return answer;
  }
  if (out.numberoftetrahedra <= 0 || out.numberofpoints <= 0 || out.numberofcorners < 4)
  {
    answer.Fail(20, "TetGen produced no tetrahedra");
    return answer;
  }
  answer.Put<std::int32_t>(out.numberofpoints);
  answer.Put(out.pointlist, 3 * sizeof(double) * static_cast<std::size_t>(out.numberofpoints));
  answer.Put<std::int32_t>(out.numberoftetrahedra);
  std::vector<std::int32_t> tets(4 * static_cast<std::size_t>(out.numberoftetrahedra));
  for (int t = 0; t < out.numberoftetrahedra; ++t)
  {
    for (int k = 0; k < 4; ++k)
    {
      tets[4 * static_cast<std::size_t>(t) + k] = out.tetrahedronlist[t * out.numberofcorners + k];
    }
  }
  answer.Put(tets.data(), tets.size() * sizeof(std::int32_t));
  return answer;
}

} // namespace

int main(int argc, char* argv[])
{
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "--serve")
  {
    for (;;)
    {
      std::uint64_t length = 0;
      if (!ReadAll(&length, sizeof(length)))
      {
        return 0; // the filter's process closed its end
      }
      if (length > (std::uint64_t(1) << 36))
      {
        return 4;
      }
      std::vector<char> request(static_cast<std::size_t>(length));
      if (!ReadAll(request.data(), request.size()))
      {
        return 0;
      }
      const Answer answer = Process(request, false);
      const std::uint64_t size = answer.Bytes.size();
      WriteAll(&size, sizeof(size));
      WriteAll(answer.Bytes.data(), answer.Bytes.size());
    }
  }
  std::vector<char> request;
  std::vector<char> buffer(1 << 16);
  for (;;)
  {
    const ssize_t r = read(0, buffer.data(), buffer.size());
    if (r <= 0)
    {
      break;
    }
    request.insert(request.end(), buffer.data(), buffer.data() + r);
  }
  const Answer answer = Process(request, mode == "--intersections");
  WriteAll(answer.Bytes.data(), answer.Bytes.size());
  return 0;
}
