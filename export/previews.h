// Pictures for people: contact sheets of shots, grids of slices, light-position plots.
// Images in, image out (OpenImageIO ImageBufAlgo style); no file I/O here.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/image.h"

namespace mesocap {

// Lays images out in a grid of `columns`, each scaled (area filter) to `thumb_width` pixels
// wide, with `gap` pixels of background between them. Labels are drawn under each thumbnail.
Image ContactSheet(const std::vector<Image>& images, const std::vector<std::string>& labels, int columns,
                   int thumb_width, int gap = 8);

// Scales an image to `width` pixels wide with an area filter (keeps aspect).
Image Thumbnail(const Image& image, int width);

// A polar plot of directions on the upper hemisphere (centre = zenith, rim = horizon),
// one dot per direction, coloured by `values` in [0,1] when given.
Image HemispherePlot(const std::vector<Eigen::Vector3d>& directions, int size, const std::string& title);

// The factor that maps the `percentile` value of `linear` to 1 (1 for an empty or black image).
float DisplayScale(const Image& linear, double percentile);

// Linear values -> display: scales so the `percentile` value maps to 1, for HDR slices.
Image ExposeForDisplay(const Image& linear, double percentile = 0.99);

// The one exposure that keeps the brightest of several images: the lowest of their display
// scales, so the images keep their relative intensities (a capture's photos). ExposeAll applies it.
float CommonDisplayScale(const std::vector<const Image*>& linear, double percentile);
std::vector<Image> ExposeAll(const std::vector<Image>& linear, double percentile = 0.99);

// A one-channel map (an error, a residual) as grey: value x `gain`, clamped to white; each value
// drawn as a square block, as large as keeps the picture at least `min_width` pixels wide.
Image GreyPicture(const Image& map, float gain, int min_width = 0);

// Several linear images under one exposure, the first one's (e.g. the truth a row of
// reconstructions is compared with): its `percentile` value maps to 1.
std::vector<Image> ExposeTogether(const std::vector<Image>& linear, double percentile = 0.99);

}  // namespace mesocap
