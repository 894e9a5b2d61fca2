// A separable filter with mirrored borders, shared by the texton analysis's Gaussian stack and the
// synthesis quality measure's Laplacian stack.
#pragma once

#include <vector>

#include "core/image.h"

namespace mesocap {

// Index into [0, n) mirrored about the end texels (OpenCV's BORDER_REFLECT_101: ..., 2, 1, 0, 1,
// 2, ...), as often as needed; 0 when n is 1.
int MirrorIndex101(int i, int n);

// Every channel of `image` convolved with `taps` (an odd count, the centre in the middle) along x,
// then along y, the taps `step` texels apart (a-trous), the border mirrored by MirrorIndex101.
// Each output sums its taps in order from the first, so results do not depend on the threads.
Image SeparableFilter(const Image& image, const std::vector<float>& taps, int step = 1, int num_threads = -1);

}  // namespace mesocap
