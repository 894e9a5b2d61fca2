// The ImageCodec (core/image_codec.h) over OpenImageIO, built as the module libmesocap_oiio.so and
// loaded on first use. Files open only with the reader their extension names: OpenImageIO's own
// open() falls back to trying every reader it has when the named one fails, so a corrupt .jpg
// would reach readers for formats no photo folder holds (its RLA reader aborts the process on some
// inputs, found by fuzz/fuzz_image_u8).
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <memory>
#include <string>

#include "core/image_codec.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;
namespace oiio = OIIO;

oiio::TypeDesc TypeOf(SampleType type) {
  switch (type) {
    case SampleType::kUint8: return oiio::TypeDesc::UINT8;
    case SampleType::kUint16: return oiio::TypeDesc::UINT16;
    case SampleType::kHalf: return oiio::TypeDesc::HALF;
    case SampleType::kFloat: return oiio::TypeDesc::FLOAT;
  }
  return oiio::TypeDesc::FLOAT;
}

ImageAttributes AttributesOf(const oiio::ImageSpec& spec) {
  ImageAttributes out;
  for (const auto& p : spec.extra_attribs) {
    const oiio::TypeDesc t = p.type();
    if (t == oiio::TypeInt || t == oiio::TypeUInt) {
      out[p.name().string()] = p.get_int();
    } else if (t == oiio::TypeFloat) {
      out[p.name().string()] = p.get_float();
    } else {
      out[p.name().string()] = p.get_string();
    }
  }
  return out;
}

void ApplyAttributes(const ImageAttributes& attributes, oiio::ImageSpec* spec) {
  for (const auto& [name, value] : attributes) {
    if (const int* i = std::get_if<int>(&value)) spec->attribute(name, *i);
    if (const float* f = std::get_if<float>(&value)) spec->attribute(name, *f);
    if (const std::string* s = std::get_if<std::string>(&value)) spec->attribute(name, *s);
  }
}

// The reader for `path`'s extension, opened at subimage `part`, or an error naming the file.
StatusOr<std::unique_ptr<oiio::ImageInput>> Open(const fs::path& path, int part) {
  const std::string extension = path.extension().string();
  auto in = extension.size() > 1 ? oiio::ImageInput::create(extension.substr(1)) : nullptr;
  if (!in) {
    oiio::geterror();  // drop OpenImageIO's pending message
    return Status::Error(path.string() + ": " +
                         (extension.size() > 1 ? "not an image: no image reader for files named *" + extension
                                               : std::string("not an image: no file extension to choose an image reader by")));
  }
  oiio::ImageSpec config, spec;
  config.attribute("raw:ColorSpace", "linear");
  if (!in->open(path.string(), spec, config)) {
    std::string why = in->geterror();
    if (why.empty()) why = "not a readable " + std::string(in->format_name()) + " file";
    return Status::Error(path.string() + ": " + why);
  }
  if (part != 0 && !in->seek_subimage(part, 0))
    return Status::Error(path.string() + ": has no part " + std::to_string(part));
  return in;
}

ImageInfo InfoOf(const oiio::ImageInput& in) {
  const oiio::ImageSpec& spec = in.spec();
  ImageInfo info;
  info.width = spec.width;
  info.height = spec.height;
  info.channels = spec.nchannels;
  info.format_name = in.format_name();
  info.bits_per_sample = int(spec.format.size()) * 8;
  if (const int bps = spec.get_int_attribute("oiio:BitsPerSample", 0); bps > 0) info.bits_per_sample = bps;
  info.stored_as_uint8 = spec.format == oiio::TypeDesc::UINT8;
  info.attributes = AttributesOf(spec);
  info.channel_names.assign(spec.channelnames.begin(), spec.channelnames.end());
  return info;
}

oiio::ImageSpec SpecOf(const fs::path& path, const EncodeRequest& image) {
  oiio::ImageSpec spec(image.width, image.height, image.channels, TypeOf(image.stored));
  std::string ext = path.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".jpg" || ext == ".jpeg") spec.attribute("Compression", "jpeg:" + std::to_string(image.jpeg_quality));
  if (ext == ".exr") spec.attribute("compression", image.exr_compression);
  if (!image.part_name.empty()) spec.attribute("name", image.part_name);
  ApplyAttributes(image.attributes, &spec);
  if (!image.channel_names.empty()) spec.channelnames = image.channel_names;
  return spec;
}

class OiioCodec final : public ImageCodec {
 public:
  std::string ExtensionList() override { return oiio::get_string_attribute("extension_list"); }

  StatusOr<ImageInfo> ReadInfo(const fs::path& path, int part) override {
    auto in = Open(path, part);
    if (!in.ok()) return in.status();
    ImageInfo info = InfoOf(**in);
    (*in)->close();
    return info;
  }

  Status Read(const fs::path& path, int part,
              const std::function<StatusOr<DecodeTarget>(const ImageInfo&)>& target) override {
    auto in = Open(path, part);
    if (!in.ok()) return in.status();
    auto into = target(InfoOf(**in));
    if (!into.ok()) return into.status();
    const bool ok = (*in)->read_image(part, 0, 0, into->channels, TypeOf(into->type), into->pixels);
    // libjpeg reports a truncated file as a warning and pads with grey: treat it as corrupt.
    std::string err = (*in)->geterror();
    (*in)->close();
    if (!ok || !err.empty()) return Status::Error(path.string() + ": " + (err.empty() ? "could not decode pixels" : err));
    return Status::Ok();
  }

  Status Write(const fs::path& file, const fs::path& path, const EncodeRequest& image) override {
    auto out = oiio::ImageOutput::create(path.string());
    if (!out) return Status::Error(path.string() + ": no image writer for this extension");
    if (!out->open(file.string(), SpecOf(path, image))) return Status::Error(path.string() + ": " + out->geterror());
    const bool wrote = out->write_image(TypeOf(image.type), image.pixels);
    const std::string err = out->geterror();
    if (!out->close() || !wrote) return Status::Error(path.string() + ": " + err);
    return Status::Ok();
  }

  Status WriteExrParts(const fs::path& file, const fs::path& path, const std::vector<EncodeRequest>& parts,
                       const std::function<StatusOr<EncodeRequest>(int part)>& pixels) override {
    if (parts.empty()) return Status::Error(path.string() + ": no parts to write");
    auto out = oiio::ImageOutput::create("openexr");
    if (!out || !out->supports("multiimage")) return Status::Error(path.string() + ": no multi-part OpenEXR writer");
    std::vector<oiio::ImageSpec> specs;
    for (const EncodeRequest& part : parts) specs.push_back(SpecOf(path, part));
    // OpenEXR requires every part's display window to be the same: the largest part's extent.
    int full_width = 0, full_height = 0;
    for (const oiio::ImageSpec& spec : specs) full_width = std::max(full_width, spec.width), full_height = std::max(full_height, spec.height);
    for (oiio::ImageSpec& spec : specs) spec.full_x = spec.full_y = 0, spec.full_width = full_width, spec.full_height = full_height;
    if (!out->open(file.string(), int(specs.size()), specs.data())) return Status::Error(path.string() + ": " + out->geterror());
    for (size_t k = 0; k < parts.size(); ++k) {
      if (k > 0 && !out->open(file.string(), specs[k], oiio::ImageOutput::AppendSubimage))
        return Status::Error(path.string() + ": part " + std::to_string(k) + ": " + out->geterror());
      auto part = pixels(int(k));
      if (!part.ok()) return part.status();
      if (part->width != parts[k].width || part->height != parts[k].height || part->channels != parts[k].channels)
        return Status::Error(path.string() + ": part " + std::to_string(k) + " is not the size its header declared");
      if (!out->write_image(TypeOf(part->type), part->pixels))
        return Status::Error(path.string() + ": part " + std::to_string(k) + ": " + out->geterror());
    }
    const std::string err = out->geterror();
    if (!out->close()) return Status::Error(path.string() + ": " + err);
    return Status::Ok();
  }
};

}  // namespace
}  // namespace mesocap

extern "C" __attribute__((visibility("default"))) mesocap::ImageCodec* MesocapImageCodec() {
  static mesocap::OiioCodec codec;
  return &codec;
}
