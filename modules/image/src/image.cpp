#include "relume/image/image.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "relume/geometry/error.h"

namespace relume {

float srgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

float linearToSrgb(float v) {
  v = std::clamp(v, 0.f, 1.f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
}

namespace {
std::string lower(std::string s) {
  for (auto& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}
}  // namespace

void imageSize(const std::string& path, int& width, int& height) {
  if (!std::filesystem::exists(path)) throw Error(path, "", "the image file does not exist");
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw Error(path, "", "cannot read the image: " + OIIO::geterror());
  width = in->spec().width;
  height = in->spec().height;
  in->close();
}

ImageRGB readImageLinear(const std::string& path) {
  if (!std::filesystem::exists(path)) throw Error(path, "", "the image file does not exist");
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw Error(path, "", "cannot read the image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels < 1)
    throw Error(path, "", "the image has no pixels");
  const int nc = spec.nchannels;
  std::vector<float> raw(size_t(spec.width) * spec.height * nc);
  if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, raw.data()))
    throw Error(path, "", "cannot decode the image: " + in->geterror());
  const bool isFloat = spec.format.is_floating_point();
  const std::string cs = lower(spec.get_string_attribute("oiio:ColorSpace"));
  const bool linear = isFloat || cs == "linear" || cs == "scene_linear";
  ImageRGB img(spec.width, spec.height);
  for (size_t i = 0, n = size_t(spec.width) * spec.height; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      float v = raw[i * nc + std::min(c, nc - 1)];
      img.pixels[i * 3 + c] = linear ? v : srgbToLinear(v);
    }
  in->close();
  return img;
}

void writeImage(const std::string& path, const ImageRGB& img, float exposure) {
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  const bool hdr = ext == ".exr" || ext == ".hdr";
  if (!hdr && ext != ".png" && ext != ".jpg" && ext != ".jpeg" && ext != ".tif" && ext != ".tiff")
    throw Error(path, "", "unknown image extension '" + ext + "' (use .exr or .png)");
  const std::string tmp = path + ".part" + ext;
  {
    auto out = OIIO::ImageOutput::create(tmp);
    if (!out) throw Error(path, "", "cannot create an image writer: " + OIIO::geterror());
    OIIO::ImageSpec spec(img.width, img.height, 3, hdr ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::UINT8);
    if (hdr) spec.attribute("compression", "zip");
    if (!out->open(tmp, spec)) throw Error(path, "", "cannot open for writing: " + out->geterror());
    bool ok;
    if (hdr) {
      ok = out->write_image(OIIO::TypeDesc::FLOAT, img.pixels.data());
    } else {
      std::vector<unsigned char> px(img.pixels.size());
      for (size_t i = 0; i < px.size(); ++i)
        px[i] = (unsigned char)std::lround(255.f * linearToSrgb(img.pixels[i] * exposure));
      ok = out->write_image(OIIO::TypeDesc::UINT8, px.data());
    }
    if (!ok || !out->close()) {
      std::remove(tmp.c_str());
      throw Error(path, "", "cannot write the image: " + out->geterror());
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw Error(path, "", "cannot move the written image into place: " + ec.message());
  }
}

}  // namespace relume
