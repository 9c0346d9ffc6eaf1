#include "basis/png.h"

#include <spng.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>

#include "basis/error.h"

namespace zbrdf {
namespace {

struct SpngContextDeleter {
  void operator()(spng_ctx* ctx) const { spng_ctx_free(ctx); }
};
using SpngContext = std::unique_ptr<spng_ctx, SpngContextDeleter>;

// PNG colour types by channel count (PNG specification, table 11.1).
constexpr uint8_t kPngColorType[5] = {0, SPNG_COLOR_TYPE_GRAYSCALE, SPNG_COLOR_TYPE_GRAYSCALE_ALPHA,
                                      SPNG_COLOR_TYPE_TRUECOLOR, SPNG_COLOR_TYPE_TRUECOLOR_ALPHA};

// Decoded pixels a reader allocates at most: a damaged or hostile header can declare 2^31 x 2^31.
constexpr size_t kMaxPngDecodedBytes = size_t{2} << 30;

// Whether PngImage's fields describe an image PNG can hold (checked by its constructor and by
// EncodePng).
bool IsPngShape(int width, int height, int channels, int bit_depth) {
  return width > 0 && height > 0 && channels >= 1 && channels <= 4 &&
         (bit_depth == 8 || bit_depth == 16);
}

}  // namespace

PngImage::PngImage(int width_in, int height_in, int channels_in, int bit_depth_in)
    : width(width_in), height(height_in), channels(channels_in), bit_depth(bit_depth_in) {
  if (!IsPngShape(width, height, channels, bit_depth)) {
    throw InputError("a PNG image of " + std::to_string(width) + "x" + std::to_string(height) +
                     " pixels, " + std::to_string(channels) + " channels of " +
                     std::to_string(bit_depth) +
                     " bits: give a positive size, 1-4 channels and 8 or 16 bits");
  }
  samples.assign(static_cast<size_t>(width) * height * channels, 0);
}

std::string EncodePng(const PngImage& image, int compression_level) {
  if (!IsPngShape(image.width, image.height, image.channels, image.bit_depth) ||
      image.samples.size() != static_cast<size_t>(image.width) * image.height * image.channels) {
    throw InputError("cannot encode a PNG of " + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + " pixels, " + std::to_string(image.channels) +
                     " channels of " + std::to_string(image.bit_depth) + " bits from " +
                     std::to_string(image.samples.size()) +
                     " samples: give 1-4 channels of 8 or 16 bits, width x height x channels "
                     "samples");
  }
  if (compression_level < -1 || compression_level > 9) {
    throw InputError("PNG compression level " + std::to_string(compression_level) +
                     " is not one of zlib's: give 0-9, or -1 for its default");
  }
  // The rows as PNG's SPNG_FMT_PNG takes them: bytes for 8 bits, host-order 16-bit words else.
  std::vector<uint8_t> bytes8;
  const void* pixels = image.samples.data();
  size_t pixel_bytes = image.samples.size() * sizeof(uint16_t);
  if (image.bit_depth == 8) {
    bytes8.resize(image.samples.size());
    for (size_t i = 0; i < image.samples.size(); ++i) {
      if (image.samples[i] > 255) {
        throw InputError("cannot encode an 8-bit PNG: sample " + std::to_string(i) + " is " +
                         std::to_string(image.samples[i]) + ", above 255");
      }
      bytes8[i] = static_cast<uint8_t>(image.samples[i]);
    }
    pixels = bytes8.data();
    pixel_bytes = bytes8.size();
  }
  const SpngContext ctx(spng_ctx_new(SPNG_CTX_ENCODER));
  if (!ctx) throw std::bad_alloc();
  spng_ihdr ihdr{};
  ihdr.width = static_cast<uint32_t>(image.width);
  ihdr.height = static_cast<uint32_t>(image.height);
  ihdr.bit_depth = static_cast<uint8_t>(image.bit_depth);
  ihdr.color_type = kPngColorType[image.channels];
  int error = spng_set_option(ctx.get(), SPNG_ENCODE_TO_BUFFER, 1);
  if (!error && compression_level >= 0) {
    error = spng_set_option(ctx.get(), SPNG_IMG_COMPRESSION_LEVEL, compression_level);
  }
  if (!error) error = spng_set_ihdr(ctx.get(), &ihdr);
  if (!error) {
    error = spng_encode_image(ctx.get(), pixels, pixel_bytes, SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE);
  }
  if (error) {
    throw InternalError(std::string("libspng cannot encode a PNG: ") + spng_strerror(error));
  }
  size_t size = 0;
  void* buffer = spng_get_png_buffer(ctx.get(), &size, &error);
  if (buffer == nullptr || error) {
    std::free(buffer);
    throw InternalError(std::string("libspng gave no PNG: ") + spng_strerror(error));
  }
  std::string png(static_cast<const char*>(buffer), size);
  std::free(buffer);
  return png;
}

PngImage DecodePng(std::string_view bytes, const std::string& what) {
  const SpngContext ctx(spng_ctx_new(0));
  if (!ctx) throw std::bad_alloc();
  const auto fail = [&what](int error) {
    return InputError(what + " is not a PNG zbrdf can read (" + spng_strerror(error) +
                      "); write it again, or give an 8- or 16-bit gray or RGB(A) PNG");
  };
  // Chunks beyond the image (text, colour profiles) are read only to be skipped: 64 MB each.
  int error = spng_set_chunk_limits(ctx.get(), 64u << 20, 64u << 20);
  if (!error) error = spng_set_png_buffer(ctx.get(), bytes.data(), bytes.size());
  spng_ihdr ihdr{};
  if (!error) error = spng_get_ihdr(ctx.get(), &ihdr);
  if (error) throw fail(error);
  int channels = 0;
  for (int c = 1; c <= 4; ++c) {
    if (ihdr.color_type == kPngColorType[c]) channels = c;
  }
  if (channels == 0 || (ihdr.bit_depth != 8 && ihdr.bit_depth != 16)) {
    throw InputError(what + " is a PNG of colour type " + std::to_string(ihdr.color_type) + " at " +
                     std::to_string(ihdr.bit_depth) +
                     " bits; zbrdf reads 8- and 16-bit gray, gray-alpha, RGB and RGBA PNGs");
  }
  size_t size = 0;
  error = spng_decoded_image_size(ctx.get(), SPNG_FMT_PNG, &size);
  if (error) throw fail(error);
  if (size > kMaxPngDecodedBytes) {
    throw InputError(what + " declares " + std::to_string(ihdr.width) + "x" +
                     std::to_string(ihdr.height) + " pixels (" + std::to_string(size >> 20) +
                     " MB decoded), more than zbrdf reads (2 GB); is the file damaged?");
  }
  std::vector<uint8_t> decoded(size);
  error = spng_decode_image(ctx.get(), decoded.data(), decoded.size(), SPNG_FMT_PNG, 0);
  // The chunks after the image, to its end: a file cut after its pixels is damaged too.
  if (!error) error = spng_decode_chunks(ctx.get());
  if (error) throw fail(error);
  PngImage image(static_cast<int>(ihdr.width), static_cast<int>(ihdr.height), channels,
                 ihdr.bit_depth);
  if (ihdr.bit_depth == 8) {
    for (size_t i = 0; i < image.samples.size(); ++i) image.samples[i] = decoded[i];
  } else {
    std::memcpy(image.samples.data(), decoded.data(), image.samples.size() * sizeof(uint16_t));
  }
  return image;
}

}  // namespace zbrdf
