#include "reconstruct/statistics_record.h"

#include "core/binary_record.h"

namespace mesocap {
namespace {

constexpr const char* kFormat = "mesocap-statistics 1";
constexpr uint64_t kMaxItems = 1u << 24;  // bounds every count read back

void PutVector(BinaryRecordWriter& w, const Eigen::Vector3d& v) { w.F64(v.x()), w.F64(v.y()), w.F64(v.z()); }
Eigen::Vector3d GetVector(BinaryRecordReader& r) {
  const double x = r.F64(), y = r.F64();
  return {x, y, r.F64()};
}

void PutTexts(BinaryRecordWriter& w, const std::vector<std::string>& texts) {
  w.U64(texts.size());
  for (const std::string& t : texts) w.Text(t);
}
std::vector<std::string> GetTexts(BinaryRecordReader& r) {
  std::vector<std::string> texts(r.Count(kMaxItems));
  for (std::string& t : texts) t = r.Text();
  return texts;
}

void PutCdfs(BinaryRecordWriter& w, const std::vector<InverseCdf>& cdfs) {
  w.U64(cdfs.size());
  for (const InverseCdf& c : cdfs) w.Floats(c.values);
}
std::vector<InverseCdf> GetCdfs(BinaryRecordReader& r) {
  std::vector<InverseCdf> cdfs(r.Count(kMaxItems));
  for (InverseCdf& c : cdfs) c.values = r.Floats();
  return cdfs;
}

void PutView(BinaryRecordWriter& w, const MeasuredView& v) {
  PutVector(w, v.view);
  w.U64(v.lights.size());
  for (const auto& l : v.lights) PutVector(w, l);
  w.U64(v.statistics.size());
  for (const SliceStatistics& s : v.statistics) {
    w.I32(s.channels), w.I32(s.band_count);
    PutCdfs(w, s.pixels), PutCdfs(w, s.bands);
  }
  w.U64(v.mean_rgb.size());
  for (const auto& m : v.mean_rgb) PutVector(w, m);
  w.U64(v.borrowed.size());
  for (const BorrowedSlice& b : v.borrowed) w.I32(b.view), w.I32(b.light), w.I32(b.image);
}
MeasuredView GetView(BinaryRecordReader& r) {
  MeasuredView v;
  v.view = GetVector(r);
  v.lights.resize(r.Count(kMaxItems));
  for (auto& l : v.lights) l = GetVector(r);
  v.statistics.resize(r.Count(kMaxItems));
  for (SliceStatistics& s : v.statistics) {
    s.channels = r.I32(), s.band_count = r.I32();
    s.pixels = GetCdfs(r), s.bands = GetCdfs(r);
  }
  v.mean_rgb.resize(r.Count(kMaxItems));
  for (auto& m : v.mean_rgb) m = GetVector(r);
  v.borrowed.resize(r.Count(kMaxItems));
  for (BorrowedSlice& b : v.borrowed) b.view = r.I32(), b.light = r.I32(), b.image = r.I32();
  return v;
}

void PutImage(BinaryRecordWriter& w, const Image& image) {
  w.I32(image.width()), w.I32(image.height()), w.I32(image.channels());
  w.Floats({image.data(), image.pixel_count() * size_t(image.channels())});
}
Image GetImage(BinaryRecordReader& r) {
  const int width = r.I32(), height = r.I32(), channels = r.I32();
  const std::vector<float> pixels = r.Floats();
  if (width < 0 || height < 0 || channels < 0 || pixels.size() != size_t(width) * size_t(height) * size_t(channels)) {
    r.MarkBroken("an image's size does not match its pixels");
    return Image();
  }
  Image image = Image::Uninitialized(width, height, channels);
  std::copy(pixels.begin(), pixels.end(), image.data());
  return image;
}

}  // namespace

Status WriteStatisticsRecord(const std::filesystem::path& file, const StatisticsRecord& record) {
  BinaryRecordWriter w(kFormat);
  const SliceSetReport& rep = record.report;
  w.I32(rep.slices_used), w.I32(rep.views), w.I32(rep.top_lights), w.I32(rep.top_board), w.U8(rep.chroma_from_top);
  PutTexts(w, rep.skipped), PutTexts(w, rep.warnings);
  w.F64(rep.seconds);
  const StatisticalBtfInputs& in = record.inputs;
  w.I32(int(in.btf_options.colour.space()));
  for (int k = 0; k < 9; ++k) w.F64(in.btf_options.colour.basis()(k / 3, k % 3));
  w.U8(in.btf_options.chromaticity_from_top_view);
  w.U64(in.top_slices.size());
  for (const Image& image : in.top_slices) PutImage(w, image);
  w.U64(in.top_lights.size());
  for (const auto& l : in.top_lights) PutVector(w, l);
  w.U64(in.views.size());
  for (const MeasuredView& v : in.views) PutView(w, v);
  return w.WriteTo(file);
}

StatusOr<StatisticsRecord> ReadStatisticsRecord(const std::filesystem::path& file, const StatisticalBtfOptions& options) {
  auto reader = BinaryRecordReader::Open(file, kFormat);
  if (!reader.ok()) return reader.status();
  BinaryRecordReader& r = *reader;
  StatisticsRecord record;
  SliceSetReport& rep = record.report;
  rep.slices_used = r.I32(), rep.views = r.I32(), rep.top_lights = r.I32(), rep.top_board = r.I32();
  rep.chroma_from_top = r.U8() != 0;
  rep.skipped = GetTexts(r), rep.warnings = GetTexts(r);
  rep.seconds = r.F64();
  StatisticalBtfInputs& in = record.inputs;
  in.btf_options = options;
  const int space = r.I32();
  Eigen::Matrix3f basis;
  for (int k = 0; k < 9; ++k) basis(k / 3, k % 3) = float(r.F64());
  if (space < 0 || space > int(ColourSpace::kChromaticity)) r.MarkBroken("an unknown colour space");
  in.btf_options.colour = ColourChannels::WithBasis(ColourSpace(space), basis);
  in.btf_options.colour_space = ColourSpace(space);
  in.btf_options.chromaticity_from_top_view = r.U8() != 0;
  in.top_slices.resize(r.Count(kMaxItems));
  for (Image& image : in.top_slices) image = GetImage(r);
  in.top_lights.resize(r.Count(kMaxItems));
  for (auto& l : in.top_lights) l = GetVector(r);
  in.views.resize(r.Count(kMaxItems));
  for (MeasuredView& v : in.views) v = GetView(r);
  MESOCAP_RETURN_IF_ERROR(r.Finish());
  return record;
}

}  // namespace mesocap
