#include "relume/image/image.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "relume/geometry/error.h"
#include "relume/geometry/memory.h"

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
  requireMemory(size_t(spec.width) * size_t(spec.height) * (size_t(nc) + 3) * sizeof(float),
                "reading this " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + " image", path);
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

namespace {
// Writes through a temporary file renamed into place, so no half-written file is ever seen.
void writeAtomically(const std::string& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc type, const void* data) {
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  const std::string tmp = path + ".part" + ext;
  {
    auto out = OIIO::ImageOutput::create(tmp);
    if (!out) throw Error(path, "", "cannot create an image writer: " + OIIO::geterror());
    if (!out->open(tmp, spec)) throw Error(path, "", "cannot open for writing: " + out->geterror());
    if (!out->write_image(type, data) || !out->close()) {
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
}  // namespace

bool isRadianceFile(const std::string& path) {
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  return ext == ".exr" || ext == ".hdr";
}

void writeImage(const std::string& path, const ImageRGB& img, float exposure) {
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  const bool hdr = isRadianceFile(path);
  if (!hdr && ext != ".png" && ext != ".jpg" && ext != ".jpeg" && ext != ".tif" && ext != ".tiff")
    throw Error(path, "", "unknown image extension '" + ext + "' (use .exr or .png)");
  OIIO::ImageSpec spec(img.width, img.height, 3, hdr ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::UINT8);
  if (hdr) {
    spec.attribute("compression", "zip");
    // No time stamp: the same pixels give the same bytes (a project saved twice is identical).
    spec.attribute("DateTime", "");
    writeAtomically(path, spec, OIIO::TypeDesc::FLOAT, img.pixels.data());
    return;
  }
  std::vector<unsigned char> px(img.pixels.size());
  for (size_t i = 0; i < px.size(); ++i) px[i] = (unsigned char)std::lround(255.f * linearToSrgb(img.pixels[i] * exposure));
  writeAtomically(path, spec, OIIO::TypeDesc::UINT8, px.data());
}

Image8 readImage8(const std::string& path) {
  if (!std::filesystem::exists(path)) throw Error(path, "", "the image file does not exist");
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw Error(path, "", "cannot read the image: " + OIIO::geterror());
  const OIIO::ImageSpec& s = in->spec();
  if (s.format.is_floating_point() || s.format.size() != 1)
    throw Error(path, "", "is not an 8-bit image (this step reads the camera's 8-bit JPEG, PNG or TIFF files)");
  if (s.width <= 0 || s.height <= 0 || s.nchannels < 1) throw Error(path, "", "the image has no pixels");
  requireMemory(size_t(s.width) * size_t(s.height) * (size_t(s.nchannels) + 3),
                "reading this " + std::to_string(s.width) + "x" + std::to_string(s.height) + " image", path);
  Image8 img;
  img.width = s.width;
  img.height = s.height;
  std::vector<unsigned char> raw(size_t(s.width) * s.height * s.nchannels);
  if (!in->read_image(0, 0, 0, s.nchannels, OIIO::TypeDesc::UINT8, raw.data()))
    throw Error(path, "", "cannot decode the image (truncated or corrupt?): " + in->geterror());
  img.pixels.resize(size_t(s.width) * s.height * 3);
  for (size_t i = 0; i < size_t(s.width) * s.height; ++i)
    for (int c = 0; c < 3; ++c) img.pixels[i * 3 + c] = raw[i * s.nchannels + (s.nchannels < 3 ? 0 : c)];
  return img;
}

void writeImage8(const std::string& path, const Image8& image, const ImageMetadata& metadata) {
  OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
  for (const auto& [k, v] : metadata.floats) spec.attribute(k, v);
  for (const auto& [k, v] : metadata.ints) spec.attribute(k, v);
  for (const auto& [k, v] : metadata.strings) spec.attribute(k, v);
  writeAtomically(path, spec, OIIO::TypeDesc::UINT8, image.pixels.data());
}


Image8 resizeImage8(const Image8& in, int width, int height) {
  if (in.width < 1 || in.height < 1 || width < 1 || height < 1) throw Error("", "image", "cannot resize an empty image");
  Image8 out;
  out.width = width;
  out.height = height;
  out.pixels.resize(size_t(width) * height * 3);
  const double sx = double(in.width) / width, sy = double(in.height) / height;
  for (int y = 0; y < height; ++y) {
    const double v = std::clamp((y + 0.5) * sy - 0.5, 0.0, in.height - 1.0);
    const int y0 = std::min(int(v), std::max(0, in.height - 2)), y1 = std::min(y0 + 1, in.height - 1);
    const double fy = v - y0;
    for (int x = 0; x < width; ++x) {
      const double u = std::clamp((x + 0.5) * sx - 0.5, 0.0, in.width - 1.0);
      const int x0 = std::min(int(u), std::max(0, in.width - 2)), x1 = std::min(x0 + 1, in.width - 1);
      const double fx = u - x0;
      for (int c = 0; c < 3; ++c) {
        auto at = [&](int xx, int yy) { return double(in.pixels[(size_t(yy) * in.width + xx) * 3 + c]); };
        out.pixels[(size_t(y) * width + x) * 3 + c] =
            (unsigned char)std::lround((1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x1, y0)) + fy * ((1 - fx) * at(x0, y1) + fx * at(x1, y1)));
      }
    }
  }
  return out;
}

}  // namespace relume
