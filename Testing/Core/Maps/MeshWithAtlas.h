// Test helper: a mesh of Testing/Data with its topology and atlas (default options unless given),
// for the tests of the atlas, its maps and the remesher built on them.
#pragma once

#include "Maps/Atlas.h"
#include "TestMeshes.h"

#include <string>

namespace beltrami
{
namespace test
{

struct MeshWithAtlas
{
  std::string Error; ///< of reading the mesh or building the atlas; empty: fine
  Mesh Surface;
  MeshTopology Topology;
  AtlasResult Atlas;

  explicit MeshWithAtlas(const std::string& name, const AtlasOptions& options = {})
    : Surface(ReadMesh(name, Error))
    , Topology(Surface.Topology())
    , Atlas(BuildAtlas(Topology, Surface.Points.data(), options))
  {
    Error = Error.empty() ? Atlas.Error : Error;
  }
  const double* Points() const { return Surface.Points.data(); }
};

} // namespace test
} // namespace beltrami
