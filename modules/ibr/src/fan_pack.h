#pragma once
// Internal to the fan files: header limits and a view's pixels packed and deflated.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "relume/ibr/fan.h"

namespace relume::ibr::detail {

// Header limits: a fan file that claims more is damaged, not a bigger fan.
inline constexpr uint32_t kMaxSize = 4096, kMaxViewsPerRing = 4096, kMaxRings = 64;

inline float srgbEncode(float c) {
  c = std::clamp(c, 0.f, 1.f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.f / 2.4f) - 0.055f;
}

// Alpha, codes, depth (row differences, high bytes then low bytes), colour: deflated.
std::vector<uint8_t> packView(const FanView& v);

}  // namespace relume::ibr::detail
