#include "capture/photo_metadata.h"

#include <cmath>
#include <cstdlib>

#include "core/text_format.h"

namespace mesocap {

const std::string* StringAttr(const ImageAttributes& attrs, const std::string& name) {
  auto it = attrs.find(name);
  if (it == attrs.end()) return nullptr;
  return std::get_if<std::string>(&it->second);
}

std::optional<double> NumberAttr(const ImageAttributes& attrs, const std::string& name) {
  auto it = attrs.find(name);
  if (it == attrs.end()) return std::nullopt;
  if (const int* i = std::get_if<int>(&it->second)) return double(*i);
  if (const float* f = std::get_if<float>(&it->second)) return double(*f);
  const std::string s = Trim(std::get<std::string>(it->second));
  if (s.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0' || !std::isfinite(v)) return std::nullopt;
  return v;
}

Json ExifOf(const ImageInfo& info) {
  Json j = Json::object();
  const auto& a = info.attributes;
  if (const std::string* s = StringAttr(a, "Make")) j["Make"] = Trim(*s);
  if (const std::string* s = StringAttr(a, "Model")) j["Model"] = Trim(*s);
  if (auto v = NumberAttr(a, "ExposureTime")) j["ExposureTime"] = *v;
  if (auto v = NumberAttr(a, "FNumber")) j["FNumber"] = *v;
  if (auto v = NumberAttr(a, "Exif:PhotographicSensitivity")) j["ISO"] = int(std::lround(*v));
  if (auto v = NumberAttr(a, "Exif:Flash")) j["Flash"] = int(std::lround(*v));
  if (auto v = NumberAttr(a, "Exif:FocalLength")) j["FocalLength"] = *v;
  if (const std::string* s = StringAttr(a, "Exif:DateTimeOriginal")) j["DateTimeOriginal"] = Trim(*s);
  j["format"] = info.format_name;
  j["width"] = info.width;
  j["height"] = info.height;
  j["bits_per_sample"] = info.bits_per_sample;
  return j;
}

}  // namespace mesocap
