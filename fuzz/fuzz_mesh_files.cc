// decorate's and render's readers of a user's files: a dressed mesh (mesh/surface_map_file.h
// ReadDressedMesh, render --map) and a direction field (mesh/tangent_frames.h ReadDirectionField,
// then CheckFieldMatchesMesh against a unit sphere, decorate --field), each on the same bytes.
#include "fuzz/fuzz_support.h"
#include "mesh/mesh_shapes.h"
#include "mesh/surface_map_file.h"
#include "mesh/tangent_frames.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto ply = mesocap::fuzz::ScratchDir() / "surface_map.ply";
  const auto field = mesocap::fuzz::ScratchDir() / "field.json";
  mesocap::fuzz::WriteBytes(ply, data, size);
  mesocap::fuzz::WriteBytes(field, data, size);
  static const mesocap::TriangleMesh sphere = mesocap::IcoSphere(1);
  mesocap::fuzz::Run([&] {
    auto dressed = mesocap::ReadDressedMesh(ply);
    mesocap::fuzz::Explain("ReadDressedMesh", dressed.status());
    if (dressed.ok()) (void)mesocap::MeasureSurfaceMap(dressed->mesh, dressed->frames, dressed->map);
    auto directions = mesocap::ReadDirectionField(field);
    mesocap::fuzz::Explain("ReadDirectionField", directions.status());
    if (directions.ok() && mesocap::CheckFieldMatchesMesh(*directions, sphere, field).ok())
      (void)mesocap::FieldFrames(sphere, *directions);
  });
  return 0;
}
