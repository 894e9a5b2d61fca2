// mesocap relight: evaluate a .ptm (formats/ptm_file.h) for one light direction and write the image.
#include "app/relight_args.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>

#include "app/commands.h"
#include "core/image_io.h"
#include "formats/ptm_file.h"
#include "reconstruct/ptm.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

bool ParseLight(const std::string& text, Eigen::Vector3d* light) {
  std::string s = text;
  for (char& ch : s)
    if (ch == ',') ch = ' ';
  std::istringstream in(s);
  double x, y, z;
  if (!(in >> x >> y >> z)) return false;
  std::string rest;
  if (in >> rest) return false;
  *light = {x, y, z};
  return std::isfinite(x) && std::isfinite(y) && std::isfinite(z) && light->norm() > 0 && z >= 0;
}

}  // namespace

int RunRelight(const RelightArgs& args) {
  const std::string verb = "relight";
  Eigen::Vector3d light;
  if (!ParseLight(args.light, &light))
    return Fail(verb, "--light must be x,y,z with z >= 0 and not all zero, not '" + args.light + "'", kExitUsage);
  if (args.bits != 8 && args.bits != 16) return Fail(verb, "--bits must be 8 or 16", kExitUsage);
  const fs::path out = args.out;
  std::string ext = out.extension().string();
  for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  if (ext != ".png" && ext != ".tif" && ext != ".tiff" && ext != ".jpg" && ext != ".jpeg")
    return Fail(verb, "--out must be a .png, .tif or .jpg file: " + args.out, kExitUsage);
  if (args.bits == 16 && (ext == ".jpg" || ext == ".jpeg"))
    return Fail(verb, "--bits 16 needs a .png or .tif output", kExitUsage);

  auto ptm = ReadPtmFile(args.ptm);
  if (!ptm.ok()) return Fail(verb, ptm.status());
  Image image = RelightPtm(*ptm, light, /*clamp=*/true, args.threads);

  // The PTM holds stored (display-encoded) values; the file must hold those same values.
  // 8-bit output is sRGB-encoded from linear by WriteImage, so decode first: the written byte is
  // then round(255 * value). 16-bit output holds linear values, i.e. the values unchanged.
  ImageWriteOptions write;
  // With --linear the values are linear already: 8-bit output encodes them to sRGB as it should.
  if (args.bits == 8) {
    write.format = PixelFormat::kUint8Srgb;
    if (!args.linear)
      for (size_t k = 0; k < image.size(); ++k) image.data()[k] = SrgbToLinear(image.data()[k]);
  } else {
    write.format = PixelFormat::kUint16Linear;
  }
  if (Status s = WriteImage(out, image, write); !s.ok()) return Fail(verb, s);
  const Eigen::Vector3d d = light.normalized();
  std::printf("%s: %dx%d relit from (%.4f, %.4f, %.4f), %d-bit%s\n", out.string().c_str(), image.width(),
              image.height(), d.x(), d.y(), d.z(), args.bits,
              args.linear && args.bits == 8 ? ", linear values sRGB-encoded" : "");
  return kExitOk;
}
}  // namespace mesocap::app
