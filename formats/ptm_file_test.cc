#include "formats/ptm_file.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>  // core/directions.h uses cross() without including it
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "capture/btf_render.h"
#include "core/directions.h"
#include "core/scratch_file.h"
#include "core/image_io.h"
#include "reconstruct/statistical_btf.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

std::string ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void WriteBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

// An independent decoder, written from the format description alone (it shares no code with
// ReadPtmFile): parses the header, decodes bytes as (byte - bias) * scale with rows stored bottom
// to top, and relights in file units (255 = full), returning values in [0, 1]. With
// `truncate_to_int` it keeps decoded coefficients as integers the way RTIViewer does
// (static_cast<int>((byte - bias) * scale)).
Image IndependentRelight(const std::string& bytes, double lu, double lv,
                         bool truncate_to_int = false) {
  std::istringstream header(bytes);
  std::string magic, format;
  int w = 0, h = 0;
  double scale[6];
  int bias[6];
  header >> magic >> format >> w >> h;
  for (double& s : scale) header >> s;
  for (int& b : bias) header >> b;
  header.get();  // the newline ending the header
  EXPECT_EQ(magic, "PTM_1.2");
  EXPECT_TRUE(header.good());
  const size_t start = size_t(header.tellg());
  const unsigned char* data = reinterpret_cast<const unsigned char*>(bytes.data()) + start;
  const double basis[6] = {lu * lu, lv * lv, lu * lv, lu, lv, 1.0};
  auto poly = [&](const unsigned char* c) {
    double sum = 0;
    for (int k = 0; k < 6; ++k) {
      double a = (double(c[k]) - bias[k]) * scale[k];
      if (truncate_to_int) a = double(static_cast<int>(a));
      sum += a * basis[k];
    }
    return sum;
  };
  Image out(w, h, 3);
  const bool lrgb = format == "PTM_FORMAT_LRGB";
  EXPECT_TRUE(lrgb || format == "PTM_FORMAT_RGB");
  EXPECT_EQ(bytes.size() - start, size_t(w) * h * (lrgb ? 9 : 18));
  for (int y = 0; y < h; ++y) {
    const int file_row = h - 1 - y;
    for (int x = 0; x < w; ++x) {
      const size_t pixel = size_t(file_row) * w + x;
      for (int c = 0; c < 3; ++c) {
        double value;
        if (lrgb) {
          const double lum = poly(data + pixel * 6);
          const unsigned char rgb = data[size_t(w) * h * 6 + pixel * 3 + c];
          value = lum * rgb / 255.0 / 255.0;
        } else {
          value = poly(data + size_t(c) * w * h * 6 + pixel * 6) / 255.0;
        }
        out.at(x, y, c) = float(std::clamp(value, 0.0, 1.0));
      }
    }
  }
  return out;
}

double Rms(const Image& a, const Image& b) {
  double sse = 0;
  for (size_t i = 0; i < a.size(); ++i) sse += std::pow(double(a.data()[i]) - b.data()[i], 2);
  return std::sqrt(sse / double(a.size()));
}

double MaxAbs(const Image& a, const Image& b) {
  double m = 0;
  for (size_t i = 0; i < a.size(); ++i)
    m = std::max(m, std::abs(double(a.data()[i]) - b.data()[i]));
  return m;
}

// A bumpy, coloured, slightly glossy surface photographed under a dome of lights.
struct Scene {
  std::vector<Eigen::Vector3d> lights, held_out;
  std::vector<Image> images;
};

Scene MakeScene(uint32_t seed, int w, int h) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  Scene s;
  s.lights.push_back({0, 0, 1});
  for (double theta : {20.0, 40.0, 60.0, 75.0})
    for (int k = 0; k < 8; ++k)
      s.lights.push_back(DirectionFromAnglesDeg(theta, 45.0 * k + theta / 2));
  for (int k = 0; k < 6; ++k)
    s.held_out.push_back(DirectionFromAnglesDeg(10 + 10 * k, 37 + 61 * k));
  std::vector<Eigen::Vector3d> normal(w * h), albedo(w * h);
  const double f1 = 0.3 + 0.2 * unit(rng), f2 = 0.2 + 0.2 * unit(rng);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double dx = 0.5 * std::cos(f1 * x) * std::sin(f2 * y),
                   dy = 0.4 * std::sin(f2 * x + f1 * y);
      normal[y * w + x] = Eigen::Vector3d(-dx, -dy, 1).normalized();
      albedo[y * w + x] = {0.2 + 0.6 * unit(rng), 0.2 + 0.5 * unit(rng), 0.1 + 0.5 * unit(rng)};
    }
  for (const auto& l : s.lights) {
    Image im(w, h, 3);
    for (int p = 0; p < w * h; ++p) {
      const double diffuse = std::max(0.0, normal[p].dot(l));
      const Eigen::Vector3d half = (l + Eigen::Vector3d::UnitZ()).normalized();
      const double spec = 0.15 * std::pow(std::max(0.0, normal[p].dot(half)), 8);
      for (int c = 0; c < 3; ++c)
        im.data()[p * 3 + c] = float(std::min(1.0, albedo[p](c) * diffuse + spec));
    }
    s.images.push_back(im);
  }
  return s;
}

}  // namespace

void PrintTo(PtmFormat format, std::ostream* os) { *os << PtmFormatToString(format); }

namespace {

// The case: a PTM fitted to a virtual-rig material (the true BTF of the weave, seen from
// the top under the Bonn lights, display-encoded as a photo would be), written to .ptm, relights
// held-out lights within 1.5/255 of the unquantised fit, and the independent decoder agrees.
TEST(PtmFileVirtualMaterial, HeldOutLightsMatchTheFloatFitAndAnIndependentDecoder) {
  auto material = Material::Create("weave");
  ASSERT_TRUE(material.ok());
  std::vector<Eigen::Vector3d> lights, held_out;
  const auto bonn = BonnDirections();
  for (size_t k = 0; k < bonn.size(); ++k) (k % 9 == 4 ? held_out : lights).push_back(bonn[k]);
  std::vector<Image> photos;
  for (const auto& l : lights) {
    Image slice = RenderTrueBtfSlice(*material, TrueBtfRequestFor(l, Eigen::Vector3d::UnitZ(), 48));
    for (size_t i = 0; i < slice.size(); ++i) slice.data()[i] = LinearToSrgb(std::min(1.0f, 4.0f * slice.data()[i]));
    photos.push_back(std::move(slice));
  }
  for (const PtmFormat format : {PtmFormat::kLrgb, PtmFormat::kRgb}) {
    SCOPED_TRACE(PtmFormatToString(format));
    PtmFitOptions options;
    options.format = format;
    const StatusOr<Ptm> fit = FitPtm(photos, lights, options);
    ASSERT_TRUE(fit.ok()) << fit.status().message();
    const fs::path file = testing::MakeTempDir() / ("weave_" + PtmFormatToString(format) + ".ptm");
    ASSERT_TRUE(WritePtmFile(file, *fit).ok());
    const StatusOr<Ptm> read = ReadPtmFile(file);
    ASSERT_TRUE(read.ok()) << read.status().message();
    const std::string bytes = ReadBytes(file);
    for (const Eigen::Vector3d& l : held_out) {
      const Image from_file = RelightPtm(*read, l);
      EXPECT_LT(Rms(RelightPtm(*fit, l), from_file), 1.5 / 255) << "light " << l.transpose();
      EXPECT_LT(MaxAbs(IndependentRelight(bytes, l.x(), l.y()), from_file), 1e-5) << "light " << l.transpose();
    }
  }
}

class PtmFileRoundTrip : public ::testing::TestWithParam<PtmFormat> {};

TEST_P(PtmFileRoundTrip, RelightsLikeTheFloatFitAndAnIndependentDecoder) {
  const PtmFormat format = GetParam();
  const int w = 37, h = 23;  // odd sizes catch row/column mix-ups
  const Scene scene = MakeScene(testing::SeedFromTestName(), w, h);
  PtmFitOptions options;
  options.format = format;
  const StatusOr<Ptm> fit = FitPtm(scene.images, scene.lights, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();

  const fs::path dir = testing::MakeTempDir();
  for (const bool integer_scales : {true, false}) {
    SCOPED_TRACE(integer_scales ? "integer scales" : "float scales");
    const fs::path file = dir / (integer_scales ? "int.ptm" : "float.ptm");
    PtmWriteOptions write_options;
    write_options.integer_scales = integer_scales;
    PtmQuantization written;
    ASSERT_TRUE(WritePtmFile(file, *fit, write_options, &written).ok());
    const std::string bytes = ReadBytes(file);
    const std::string expected_start =
        std::string("PTM_1.2\n") +
        (format == PtmFormat::kLrgb ? "PTM_FORMAT_LRGB" : "PTM_FORMAT_RGB") + "\n37\n23\n";
    ASSERT_EQ(bytes.substr(0, expected_start.size()), expected_start);

    PtmQuantization read_q;
    const StatusOr<Ptm> read = ReadPtmFile(file, &read_q);
    ASSERT_TRUE(read.ok()) << read.status().message();
    EXPECT_EQ(read->format, format);
    EXPECT_EQ(read->width(), w);
    EXPECT_EQ(read->height(), h);
    EXPECT_EQ(read_q.scale, written.scale);
    EXPECT_EQ(read_q.bias, written.bias);

    std::vector<Eigen::Vector3d> test_lights = scene.held_out;
    test_lights.push_back(scene.lights[5]);
    double worst_rms = 0;
    for (const Eigen::Vector3d& l : test_lights) {
      const Image from_fit = RelightPtm(*fit, l);
      const Image from_file = RelightPtm(*read, l);
      const double rms = Rms(from_fit, from_file);
      worst_rms = std::max(worst_rms, rms);
      EXPECT_LT(rms, 1.5 / 255) << "light " << l.transpose() << ": rms " << rms * 255 << "/255";
      const Eigen::Vector3d d = l.normalized();
      const Image independent = IndependentRelight(bytes, d.x(), d.y());
      EXPECT_LT(MaxAbs(independent, from_file), 1e-5) << "light " << l.transpose();
      if (integer_scales) {  // a viewer that truncates coefficients to int sees the same image
        const Image truncating = IndependentRelight(bytes, d.x(), d.y(), true);
        EXPECT_LT(MaxAbs(truncating, from_file), 1e-5) << "light " << l.transpose();
      }
    }
    RecordProperty(
        integer_scales ? "worst_rms_over_255_integer_scales" : "worst_rms_over_255_float_scales",
        std::to_string(worst_rms * 255));
    // Re-writing what was read gives the same coefficients: they sit on the quantisation grid.
    const fs::path again = dir / "again.ptm";
    ASSERT_TRUE(WritePtmFile(again, *read, write_options).ok());
    const StatusOr<Ptm> reread = ReadPtmFile(again);
    ASSERT_TRUE(reread.ok());
    EXPECT_LT(MaxAbs(RelightPtm(*reread, scene.held_out[2]), RelightPtm(*read, scene.held_out[2])),
              1e-5);
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, PtmFileRoundTrip,
                         ::testing::Values(PtmFormat::kLrgb, PtmFormat::kRgb),
                         [](const auto& info) { return PtmFormatToString(info.param); });

TEST(PtmFile, QuantisationNeverClipsAndUsesTheFullByteRange) {
  std::mt19937 rng(testing::SeedFromTestName());
  Ptm ptm;
  ptm.format = PtmFormat::kRgb;
  ptm.coefficients = Image(9, 7, 18);
  // Ranges of every kind: all positive, all negative, lopsided, symmetric, constant, zero.
  const double lo[6] = {0.1, -3.0, -0.02, -1.0, 0.37, 0.0};
  const double hi[6] = {2.5, -0.5, 1.7, 1.0, 0.37, 0.0};
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 9; ++x)
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 6; ++k) {
          std::uniform_real_distribution<double> d(lo[k], hi[k] + 1e-12);
          ptm.coefficients.at(x, y, c * 6 + k) = float(d(rng));
        }
  ptm.coefficients.at(0, 0, 0) = float(lo[0]);
  ptm.coefficients.at(8, 6, 17) = 0.0f;  // a5 of blue stays zero: range [0, 0]
  const fs::path dir = testing::MakeTempDir();
  for (const bool integer_scales : {true, false}) {
    SCOPED_TRACE(integer_scales ? "integer scales" : "float scales");
    const fs::path file = dir / "ranges.ptm";
    PtmWriteOptions options;
    options.integer_scales = integer_scales;
    PtmQuantization q;
    ASSERT_TRUE(WritePtmFile(file, ptm, options, &q).ok());
    const StatusOr<Ptm> read = ReadPtmFile(file);
    ASSERT_TRUE(read.ok()) << read.status().message();
    for (int k = 0; k < 6; ++k) {
      EXPECT_GE(q.bias[k], 0);
      EXPECT_LE(q.bias[k], 255);
      EXPECT_GT(q.scale[k], 0.0f);
      if (integer_scales) {
        EXPECT_EQ(q.scale[k], std::round(q.scale[k]));
      }
    }
    if (!integer_scales) {
      // Constant-sign ranges use a bias at the end of the byte range, mixed ones in between.
      EXPECT_EQ(q.bias[0], 0);
      EXPECT_EQ(q.bias[1], 255);
      EXPECT_GT(q.bias[3], 100);
      EXPECT_LT(q.bias[3], 155);
    }
    for (size_t i = 0; i < ptm.coefficients.size(); ++i) {
      const int k = int(i % 6);
      const double step = q.scale[k] / 255.0;  // in Ptm units
      const double decoded = read->coefficients.data()[i];
      EXPECT_LE(std::abs(decoded - ptm.coefficients.data()[i]), 0.5 * step + 1e-6)
          << "coefficient a" << k;
      if (integer_scales) {
        EXPECT_NEAR(decoded * 255, std::round(decoded * 255), 1e-3);
      }
    }
    if (integer_scales) {
      // The smallest whole numbers that cover each range in 256 byte values (file units = 255x).
      const float expected[6] = {3, 3, 2, 2, 1, 1};  // 637.5, -765, [-5.1, 433.5], +-255, 94, 0
      for (int k = 0; k < 6; ++k) EXPECT_EQ(q.scale[k], expected[k]) << "a" << k;
    } else {
      // The step is the finest that covers the range (the range spans ~255 steps).
      EXPECT_LT(q.scale[0] / 255.0, (2.5 - 0.0) / 254.0);
      EXPECT_LT(q.scale[1] / 255.0, 3.0 / 254.0);
    }
  }
}

TEST(PtmFile, RowsAreStoredBottomToTop) {
  Ptm ptm;
  ptm.format = PtmFormat::kLrgb;
  ptm.coefficients = Image(2, 3, 6);
  ptm.rgb = Image(2, 3, 3, 0.5f);
  ptm.coefficients.at(0, 2, 5) = 1.0f;  // bottom-left pixel: constant term 1
  ptm.rgb.at(1, 2, 0) = 1.0f;           // bottom-right pixel: red 255
  const fs::path file = testing::MakeTempDir() / "rows.ptm";
  PtmQuantization q;
  ASSERT_TRUE(WritePtmFile(file, ptm, {}, &q).ok());
  const std::string bytes = ReadBytes(file);
  const size_t data = bytes.size() - 2 * 3 * 9;
  EXPECT_NEAR((int(static_cast<unsigned char>(bytes[data + 5])) - q.bias[5]) * q.scale[5], 255.0,
              1.0);
  // First RGB row (the bottom one), second pixel.
  EXPECT_EQ(static_cast<unsigned char>(bytes[data + 2 * 3 * 6 + 3]), 255);
  EXPECT_EQ(static_cast<unsigned char>(bytes[data + 2 * 3 * 6 + 0]), 128);
}

// The file body written the slow, obvious way (docs/formats.md): per polynomial, rows bottom to
// top, six bytes a pixel, round(255 * coefficient / scale + bias) clamped to a byte; then, for
// LRGB, the colour bytes. The writer fills rows in parallel: every byte must be this one.
std::string ReferenceBody(const Ptm& ptm, const PtmQuantization& q) {
  std::string body;
  auto byte = [](double v) { return char(static_cast<unsigned char>(std::clamp(std::nearbyint(v), 0.0, 255.0))); };
  for (int c = 0; c < ptm.polynomials(); ++c)
    for (int y = ptm.height() - 1; y >= 0; --y)
      for (int x = 0; x < ptm.width(); ++x)
        for (int k = 0; k < 6; ++k)
          body += byte(255.0 * ptm.coefficients.at(x, y, c * 6 + k) * (1.0 / double(q.scale[k])) + q.bias[k]);
  if (ptm.format == PtmFormat::kLrgb)
    for (int y = ptm.height() - 1; y >= 0; --y)
      for (int x = 0; x < ptm.width(); ++x)
        for (int c = 0; c < 3; ++c) body += byte(255.0 * ptm.rgb.at(x, y, c));
  return body;
}

TEST(PtmFile, ParallelWritingGivesTheReferenceBytes) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::normal_distribution<float> coefficient(0.0f, 0.4f);
  std::uniform_real_distribution<float> colour(0.0f, 1.0f);
  for (PtmFormat format : {PtmFormat::kLrgb, PtmFormat::kRgb})
    for (bool integer_scales : {true, false}) {
      Ptm ptm;
      ptm.format = format;
      const int polynomials = format == PtmFormat::kRgb ? 3 : 1;
      ptm.coefficients = Image(97, 61, 6 * polynomials);  // odd sizes: no row block is whole
      for (size_t i = 0; i < ptm.coefficients.size(); ++i) ptm.coefficients.data()[i] = coefficient(rng);
      if (format == PtmFormat::kLrgb) {
        ptm.rgb = Image(97, 61, 3);
        for (size_t i = 0; i < ptm.rgb.size(); ++i) ptm.rgb.data()[i] = colour(rng);
      }
      const fs::path file = testing::MakeTempDir() / "parallel.ptm";
      PtmQuantization q;
      ASSERT_TRUE(WritePtmFile(file, ptm, {.integer_scales = integer_scales}, &q).ok());
      const std::string bytes = ReadBytes(file);
      const std::string reference = ReferenceBody(ptm, q);
      ASSERT_GT(bytes.size(), reference.size());
      EXPECT_TRUE(bytes.compare(bytes.size() - reference.size(), reference.size(), reference) == 0)
          << PtmFormatToString(format) << (integer_scales ? " integer" : " float") << " scales";
      // The same PTM parked in a scratch file row by row, as fit-ptm does, and written from
      // there: the same file.
      const fs::path parked_file = file.parent_path() / "parked.ptm";
      auto scratch = ScratchFile::Create(file.parent_path());
      ASSERT_TRUE(scratch.ok()) << scratch.status().message();
      const size_t row_floats = size_t(ptm.width()) * ptm.coefficients.channels(), rgb_floats = size_t(ptm.width()) * 3;
      const uint64_t rgb_start = uint64_t(ptm.height()) * row_floats * sizeof(float);
      PtmRowSource parked{format, ptm.width(), ptm.height(), CoefficientRange::Empty(), {}, {}};
      for (int y = ptm.height() - 1; y >= 0; --y) {  // any order
        parked.range.Include(RowCoefficientRange(ptm.coefficients.row(y), int(row_floats)));
        ASSERT_TRUE(scratch->Write(y * row_floats * sizeof(float), ptm.coefficients.row(y), row_floats * sizeof(float)).ok());
        if (format == PtmFormat::kLrgb) {
          ASSERT_TRUE(scratch->Write(rgb_start + y * rgb_floats * sizeof(float), ptm.rgb.row(y), rgb_floats * sizeof(float)).ok());
        }
      }
      const auto read = [&](uint64_t offset, size_t floats, std::vector<float>* buffer) -> StatusOr<const float*> {
        buffer->resize(floats);
        MESOCAP_RETURN_IF_ERROR(scratch->Read(offset, buffer->data(), floats * sizeof(float)));
        return buffer->data();
      };
      parked.coefficients = [&](int y, std::vector<float>* buffer) { return read(y * row_floats * sizeof(float), row_floats, buffer); };
      parked.rgb = [&](int y, std::vector<float>* buffer) {
        return read(rgb_start + y * rgb_floats * sizeof(float), rgb_floats, buffer);
      };
      PtmQuantization parked_q;
      ASSERT_TRUE(WritePtmFile(parked_file, parked, {.integer_scales = integer_scales}, &parked_q).ok());
      EXPECT_EQ(parked_q.scale, q.scale);
      EXPECT_EQ(parked_q.bias, q.bias);
      EXPECT_TRUE(ReadBytes(parked_file) == bytes) << PtmFormatToString(format) << ": written from parked rows";
    }
}

TEST(PtmFile, ARowThatCannotBeReadFailsTheWriteAndLeavesNoFile) {
  Ptm ptm;
  ptm.format = PtmFormat::kRgb;
  ptm.coefficients = Image(40, 300, 18, 0.25f);
  PtmRowSource rows{ptm.format, ptm.width(), ptm.height(), RowCoefficientRange(ptm.coefficients.data(), 18), {}, {}};
  rows.coefficients = [&](int y, std::vector<float>*) -> StatusOr<const float*> {
    if (y == 211) return Status::Error("scratch: cannot read back row 211");
    return ptm.coefficients.row(y);
  };
  const fs::path file = testing::MakeTempDir() / "failed.ptm";
  const Status st = WritePtmFile(file, rows);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.message().find("row 211"), std::string::npos) << st.message();
  EXPECT_FALSE(fs::exists(file));
  rows.range.finite = false;
  EXPECT_FALSE(WritePtmFile(file, rows).ok());
}

class PtmFileErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::MakeTempDir();
    good_ = dir_ / "good.ptm";
    Ptm ptm;
    ptm.format = PtmFormat::kLrgb;
    ptm.coefficients = Image(4, 3, 6, 0.25f);
    ptm.rgb = Image(4, 3, 3, 0.5f);
    ASSERT_TRUE(WritePtmFile(good_, ptm).ok());
    bytes_ = ReadBytes(good_);
  }
  void ExpectError(const std::string& contents, const std::string& fragment) {
    const fs::path bad = dir_ / "bad.ptm";
    WriteBytes(bad, contents);
    const StatusOr<Ptm> read = ReadPtmFile(bad);
    ASSERT_FALSE(read.ok()) << "accepted a file that should fail with '" << fragment << "'";
    EXPECT_NE(read.status().message().find(bad.string()), std::string::npos)
        << read.status().message();
    EXPECT_NE(read.status().message().find(fragment), std::string::npos) << read.status().message();
  }
  std::string Replace(const std::string& from, const std::string& to) {
    std::string s = bytes_;
    s.replace(s.find(from), from.size(), to);
    return s;
  }
  fs::path dir_, good_;
  std::string bytes_;
};

TEST_F(PtmFileErrors, TruncatedAndOverlongData) {
  ASSERT_TRUE(ReadPtmFile(good_).ok());
  ExpectError(bytes_.substr(0, bytes_.size() - 1), "truncated PTM file");
  ExpectError(bytes_.substr(0, bytes_.size() - 4 * 3 * 9),
              "needs 108 bytes after the header, found 0");
  ExpectError(bytes_ + "x", "1 unexpected bytes");
  ExpectError(bytes_.substr(0, 20), "truncated PTM header");
  ExpectError("", "the file is empty");
}

TEST_F(PtmFileErrors, MalformedHeaders) {
  ExpectError(Replace("PTM_1.2", "PTM_1.1"), "first line must be PTM_1.2");
  ExpectError("\x89PNG\r\n\x1a\n garbage", "not a PTM 1.2 file");
  ExpectError(Replace("PTM_FORMAT_LRGB", "PTM_FORMAT_JPEG_LRGB"), "unsupported PTM format");
  ExpectError(Replace("PTM_FORMAT_LRGB", "HELLO"), "not a PTM format name");
  ExpectError(Replace("\n4\n3\n", "\n4\nx\n"), "height 'x' is not an integer");
  ExpectError(Replace("\n4\n3\n", "\n0\n3\n"), "width '0' is not an integer in [1,");
  ExpectError(Replace("\n4\n3\n", "\n-4\n3\n"), "width '-4'");
  // A non-numeric scale, a non-integer bias, a header without its final newline.
  std::string s = bytes_;
  s.insert(s.find("\n3\n") + 3, "abc ");
  ExpectError(s, "scale 0 'abc' is not a finite number");
  size_t line5 = 0;
  for (int i = 0; i < 5; ++i) line5 = bytes_.find('\n', line5) + 1;
  const size_t line6_end = bytes_.find('\n', line5);
  std::string b = bytes_;
  b.replace(line5, line6_end - line5, "0 0 0 0 0 1.5");
  ExpectError(b, "bias 5 '1.5' is not an integer");
  b = bytes_;
  b.replace(line5, line6_end - line5 + 1, "0 0 0 0 0 0 ");
  ExpectError(b, "must end with a newline");
}

TEST_F(PtmFileErrors, ScalesWhoseDecodedRangeIsNotFiniteAreRefused) {
  // Every scale finite, every bias in range, but byte 255 would decode to 255 * 3e38: relighting
  // such a file made inf and NaN.
  size_t line4 = 0;
  for (int i = 0; i < 4; ++i) line4 = bytes_.find('\n', line4) + 1;
  std::string s = bytes_;
  s.replace(line4, bytes_.find('\n', line4) - line4, "1 1 3e38 1 1 1");
  ExpectError(s, "scale 2");
  ExpectError(s, "decodes to coefficients beyond");
}

TEST(PtmFile, MissingFileAndUnwritablePath) {
  const fs::path dir = testing::MakeTempDir();
  const StatusOr<Ptm> read = ReadPtmFile(dir / "nope.ptm");
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.status().message().find("nope.ptm"), std::string::npos);
  Ptm ptm;
  ptm.coefficients = Image(2, 2, 6);
  ptm.rgb = Image(2, 2, 3);
  const Status st = WritePtmFile(dir / "no_such_folder" / "x.ptm", ptm);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("x.ptm"), std::string::npos) << st.message();
  // Inconsistent or non-finite data is refused, and nothing is left behind.
  ptm.rgb = Image();
  EXPECT_FALSE(WritePtmFile(dir / "bad.ptm", ptm).ok());
  ptm.rgb = Image(2, 2, 3);
  ptm.coefficients.at(1, 1, 2) = std::nanf("");
  const Status nan = WritePtmFile(dir / "bad.ptm", ptm);
  EXPECT_FALSE(nan.ok());
  EXPECT_NE(nan.message().find("pixel (1, 1)"), std::string::npos) << nan.message();
  EXPECT_TRUE(fs::is_empty(dir));
}

}  // namespace
}  // namespace mesocap
