// OFF reader and writer: variants, exact round trip, hostile files, fuzzing.
#include "TestHelpers.h"

#include "vtkOFFReader.h"
#include "vtkOFFWriter.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkExecutive.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

using beltrami::test::DataFile;
using beltrami::test::MessageCollector;

namespace
{

/// A file of the test output directory that belongs to the running test:
/// ctest runs the tests of this file in parallel (each its own process), and
/// a shared name let one test read another's file.
std::string TempFile(const std::string& name)
{
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  return std::string(BELTRAMI_TEST_OUTPUT_DIR) + "/" + (test ? std::string(test->name()) + "-" : "") + name;
}

void WriteText(const std::string& path, const std::string& text)
{
  std::ofstream(path, std::ios::binary) << text;
}

struct ReadResult
{
  vtkSmartPointer<vtkPolyData> Output;
  bool Ok;
  std::string Error;
};

ReadResult Read(const std::string& path)
{
  vtkNew<vtkOFFReader> reader;
  MessageCollector* messages = MessageCollector::New();
  messages->Watch(reader);
  // The executive reports a failed RequestData too.
  messages->Watch(reader->GetExecutive());
  reader->SetFileName(path.c_str());
  reader->Update();
  ReadResult r{ vtkSmartPointer<vtkPolyData>::New(), messages->Errors.empty(),
    reader->GetLastErrorMessage() };
  r.Output->ShallowCopy(reader->GetOutput());
  messages->Delete();
  return r;
}

ReadResult ReadText(const std::string& text)
{
  const std::string path = TempFile("test.off");
  WriteText(path, text);
  return Read(path);
}

} // namespace

TEST(OFFReader, VariantsCommentsPolygonsAndColours)
{
  const auto r = ReadText("# a comment\n"
                          "COFF # colours follow\n"
                          "\n"
                          "5 3 0\n"
                          "0 0 0 255 0 0\n"
                          "1 0 0 0 255 0 128\n"
                          "1 1 0   0.0 0.0 1.0\n"
                          "0 1 0 10 20 30\n"
                          "0.5 2 1e-1 0 0 0\n"
                          "3 0 1 2\n"
                          "4 0 2 3 4 0.5 0.5 0.5\n"
                          "3 0 3 4 1 2 3\n");
  ASSERT_TRUE(r.Ok) << r.Error;
  vtkPolyData* pd = r.Output;
  EXPECT_EQ(pd->GetNumberOfPoints(), 5);
  EXPECT_EQ(pd->GetNumberOfPolys(), 3);
  EXPECT_DOUBLE_EQ(pd->GetPoint(4)[2], 0.1);
  vtkNew<vtkIdList> ids;
  pd->GetCellPoints(1, ids);
  EXPECT_EQ(ids->GetNumberOfIds(), 4);
  auto* colors = vtkUnsignedCharArray::SafeDownCast(pd->GetPointData()->GetArray("Colors"));
  ASSERT_NE(colors, nullptr);
  EXPECT_EQ(colors->GetNumberOfComponents(), 4); // one vertex had alpha
  EXPECT_EQ(colors->GetValue(4 * 1 + 3), 128);
  EXPECT_EQ(colors->GetValue(4 * 2 + 2), 255); // float colour 1.0
  EXPECT_EQ(colors->GetValue(4 * 3 + 1), 20);
  auto* faceColors = vtkUnsignedCharArray::SafeDownCast(pd->GetCellData()->GetArray("Colors"));
  ASSERT_NE(faceColors, nullptr);
  EXPECT_EQ(faceColors->GetValue(3 * 1), 128);
  EXPECT_EQ(faceColors->GetValue(3 * 2 + 2), 3);

  const auto n = ReadText("NOFF 3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n");
  ASSERT_TRUE(n.Ok) << n.Error;
  ASSERT_NE(n.Output->GetPointData()->GetNormals(), nullptr);
  EXPECT_EQ(n.Output->GetPointData()->GetNormals()->GetComponent(2, 2), 1.0);

  const auto st = ReadText("STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n");
  ASSERT_TRUE(st.Ok) << st.Error;
  ASSERT_NE(st.Output->GetPointData()->GetTCoords(), nullptr);
  EXPECT_EQ(st.Output->GetPointData()->GetTCoords()->GetComponent(2, 1), 1.0);

  const auto noHeader = ReadText("3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_TRUE(noHeader.Ok) << noHeader.Error;
}

TEST(OFFReader, ReadsEveryRealMesh)
{
  const struct
  {
    const char* File;
    vtkIdType Points, Faces;
  } meshes[] = { { "bunny00.off", 37706, 75408 }, { "eight.off", 315, 634 },
    { "knot1.off", 3200, 6400 }, { "mushroom.off", 2337, 4608 } };
  for (const auto& m : meshes)
  {
    const auto r = Read(DataFile(m.File));
    ASSERT_TRUE(r.Ok) << m.File << ": " << r.Error;
    EXPECT_EQ(r.Output->GetNumberOfPoints(), m.Points);
    EXPECT_EQ(r.Output->GetNumberOfPolys(), m.Faces);
  }
  EXPECT_EQ(vtkOFFReader::CanReadFile(DataFile("eight.off").c_str()), 1);
  // Comment lines before the header (CGAL's tools write them): ParaView
  // picks the reader by CanReadFile.
  const std::string commented = TempFile("commented.off");
  WriteText(commented, "# Output of a CGAL tool\n#CBP\n\n  COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n3 0 1 2\n");
  EXPECT_EQ(vtkOFFReader::CanReadFile(commented.c_str()), 1);
  const std::string text = TempFile("not-off.txt");
  WriteText(text, "# a comment\nsolid cube\nOFF later\n");
  EXPECT_EQ(vtkOFFReader::CanReadFile(text.c_str()), 0);
}

TEST(OFFWriter, RoundTripIsExact)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  sphere->SetCenter(0.1, 1.0 / 3.0, -7e-9);
  sphere->Update();
  vtkNew<vtkPolyData> in;
  in->DeepCopy(sphere->GetOutput());
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(3);
  colors->SetNumberOfTuples(in->GetNumberOfPoints());
  for (vtkIdType i = 0; i < 3 * in->GetNumberOfPoints(); ++i)
  {
    colors->SetValue(i, static_cast<unsigned char>(i % 251));
  }
  in->GetPointData()->AddArray(colors);

  vtkNew<vtkOFFWriter> writer;
  writer->SetInputData(in);
  writer->SetFileName(TempFile("roundtrip.off").c_str());
  ASSERT_EQ(writer->Write(), 1);
  const auto r = Read(TempFile("roundtrip.off"));
  ASSERT_TRUE(r.Ok) << r.Error;
  ASSERT_EQ(r.Output->GetNumberOfPoints(), in->GetNumberOfPoints());
  ASSERT_EQ(r.Output->GetNumberOfPolys(), in->GetNumberOfPolys());
  for (vtkIdType i = 0; i < in->GetNumberOfPoints(); ++i)
  {
    for (int d = 0; d < 3; ++d)
    {
      EXPECT_EQ(r.Output->GetPoint(i)[d], in->GetPoint(i)[d]); // bit-exact
    }
  }
  vtkNew<vtkIdList> a, b;
  for (vtkIdType c = 0; c < in->GetNumberOfPolys(); ++c)
  {
    in->GetCellPoints(c, a);
    r.Output->GetCellPoints(c, b);
    ASSERT_EQ(a->GetNumberOfIds(), b->GetNumberOfIds());
    for (vtkIdType k = 0; k < a->GetNumberOfIds(); ++k)
    {
      EXPECT_EQ(a->GetId(k), b->GetId(k));
    }
  }
  auto* back = vtkUnsignedCharArray::SafeDownCast(r.Output->GetPointData()->GetArray("Colors"));
  ASSERT_NE(back, nullptr);
  for (vtkIdType i = 0; i < 3 * in->GetNumberOfPoints(); ++i)
  {
    EXPECT_EQ(back->GetValue(i), colors->GetValue(i));
  }
}

TEST(OFFReader, HostileFilesGiveClearErrors)
{
  const struct
  {
    const char* Text;
    const char* Message;
  } cases[] = {
    { "", "empty file" },
    { "PLY\n3 1 0\n", "not an OFF file" },
    { "OFF BINARY\n", "binary" },
    { "4OFF\n1 0 0\n0 0 0 0\n", "4D" },
    { "OFF\n", "missing vertex and face counts" },
    { "OFF\n-3 1 0\n", "non-negative" },
    { "OFF\n999999999999 999999999999 0\n0 0 0\n", "truncated" },
    { "OFF\n99999999999999999999999 1 0\n", "non-negative" },
    { "OFF\n3 1 0\n0 0 0\n1 0 0\n", "truncated" },
    { "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", "too few values" },
    { "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", "non-finite" },
    { "OFF\n3 1 0\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n", "non-finite" },
    { "OFF\n3 1 0\n0 0 0\n1 0x 0\n0 1 0\n3 0 1 2\n", "invalid" },
    { "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "not in [0, 3)" },
    { "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "not in [0, 3)" },
    { "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n1000000000 0 1 2\n", "more vertices than the line" },
    { "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "at least 3" },
    { "COFF\n3 1 0\n0 0 0 300 0 0\n1 0 0 1 1 1\n0 1 0 1 1 1\n3 0 1 2\n", "colour" },
  };
  for (const auto& c : cases)
  {
    const auto r = ReadText(c.Text);
    EXPECT_FALSE(r.Ok) << c.Text;
    EXPECT_NE(r.Error.find(c.Message), std::string::npos) << "'" << r.Error << "' for " << c.Text;
    EXPECT_EQ(r.Output->GetNumberOfPoints(), 0) << c.Text;
  }
  const auto missing = Read(TempFile("does-not-exist.off"));
  EXPECT_FALSE(missing.Ok);
  EXPECT_NE(missing.Error.find("cannot open"), std::string::npos);
}

// A few hundred mutations of a valid file: the reader must never crash, hang
// or allocate wildly, and must either fail cleanly or return a consistent mesh.
TEST(OFFReader, Fuzz)
{
  std::ifstream in(DataFile("eight.off"), std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string original = buffer.str();
  std::mt19937 rng(20261122);
  const char* tokens[] = { "-1", "0", "3", "99999999999", "1e308", "nan", "-inf", "#", "\n", " ",
    "OFF", "COFF", "4294967296", "9223372036854775807", "x", "3.5", "" };
  int failures = 0, successes = 0;
  for (int iteration = 0; iteration < 400; ++iteration)
  {
    std::string text = original;
    const int mutations = 1 + iteration % 5;
    for (int m = 0; m < mutations; ++m)
    {
      std::uniform_int_distribution<std::size_t> pos(0, text.empty() ? 0 : text.size() - 1);
      switch (rng() % 6)
      {
        case 0: // bit flip
          if (!text.empty())
          {
            text[pos(rng)] ^= static_cast<char>(1u << (rng() % 8));
          }
          break;
        case 1: // truncation
          text.resize(pos(rng));
          break;
        case 2: // token insertion
          text.insert(pos(rng), std::string(" ") + tokens[rng() % std::size(tokens)] + " ");
          break;
        case 3: // line deletion
        {
          const std::size_t a = text.find('\n', pos(rng));
          const std::size_t b = a == std::string::npos ? a : text.find('\n', a + 1);
          if (b != std::string::npos)
          {
            text.erase(a, b - a);
          }
          break;
        }
        case 4: // line duplication
        {
          const std::size_t a = text.find('\n', pos(rng));
          const std::size_t b = a == std::string::npos ? a : text.find('\n', a + 1);
          if (b != std::string::npos)
          {
            text.insert(b, text.substr(a, b - a));
          }
          break;
        }
        default: // replace the header counts
          text.replace(0, std::min<std::size_t>(text.size(), 12),
            std::string("OFF\n") + tokens[rng() % std::size(tokens)] + " " +
              tokens[rng() % std::size(tokens)] + " 0\n");
          break;
      }
    }
    const auto r = ReadText(text);
    if (!r.Ok)
    {
      ++failures;
      EXPECT_FALSE(r.Error.empty());
      EXPECT_EQ(r.Output->GetNumberOfPoints(), 0);
      continue;
    }
    ++successes;
    vtkPolyData* pd = r.Output;
    EXPECT_LE(pd->GetNumberOfPoints(), static_cast<vtkIdType>(text.size()));
    const vtkIdType n = pd->GetNumberOfPoints();
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
    {
      pd->GetCellPoints(c, ids);
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      {
        ASSERT_TRUE(ids->GetId(k) >= 0 && ids->GetId(k) < n);
      }
    }
    for (vtkIdType i = 0; i < n; ++i)
    {
      const double* p = pd->GetPoint(i);
      ASSERT_TRUE(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]));
    }
  }
  std::printf("fuzz: %d mutated files rejected with an error, %d read consistently\n", failures,
    successes);
  EXPECT_GT(failures, 100);
}
