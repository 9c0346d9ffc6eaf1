// One camera pixel's row of the light transport, packed in 4 bytes per entry, and its product
// with a pattern's projector radiance: the inner loop of every simulated frame
// (docs/simulator.md, "Transport storage").
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace zbrdf {

// A transport entry: its projector pixel as a step from the previous entry's (the first entry's
// from the row's first index), and its weight in units of the row's scale.
struct TransportEntry {
  // Left unset: a transport's hundreds of MB are allocated and then written whole (the build's
  // rows copied in by both threads, a cache file read in), and zeroing them first had cost a
  // pass over memory on one thread, most of it the kernel's first touch of every page.
  TransportEntry() {}  // NOLINT(modernize-use-equals-default): "= default" would zero them
  TransportEntry(uint16_t step_in, int16_t weight_in) : step(step_in), weight(weight_in) {}
  uint16_t step;
  int16_t weight;
};

// A sample's contribution before packing: projector pixel and weight.
struct TransportSample {
  uint32_t index;
  float weight;
};

// Packs one camera pixel's samples, in ascending projector pixel without repeats, onto the end of
// *row: steps from the previous pixel (the first from the returned first index; a gap beyond
// 65535 takes zero-weight steps of 65535) and weights rounded to nearest (ties to even) in units of
// the returned scale, chosen so that the largest |weight| is 32767 (the rounding is at most scale /
// 2). With no samples, or only zero weights, nothing is appended and the scale is 0.
struct PackedRowStart {
  uint32_t first_index = 0;
  float scale = 0;
};
PackedRowStart AppendPackedRow(std::span<const TransportSample> samples,
                               std::vector<TransportEntry>* row);
// The same written to out[0 .. *count), which must have room for PackedRowMaxEntries(
// samples.size(), projector_pixels) entries when every index is below projector_pixels: the
// transport build packs each pixel straight into its row's place in the whole transport.
PackedRowStart PackRow(std::span<const TransportSample> samples, TransportEntry* out,
                       size_t* count);
// The most entries a row of `samples` samples packs into: one per sample, and the gap steps,
// fewer than projector_pixels / 65535 + 1 since the steps add up to less than projector_pixels.
inline size_t PackedRowMaxEntries(size_t samples, uint32_t projector_pixels) {
  return samples + projector_pixels / 0xffffu + 1;
}

// sum over the row of weight * radiance[j], j = first + the steps up to and including the
// entry's: each product rounded to float (exact for the weight, which has 16 bits), summed in
// double in one fixed order: four partial sums, entry e into sum e mod 4 in entry order, then
// (s0 + s1) + (s2 + s3). Every path below keeps that order, so they agree bit for bit: a frame
// does not depend on the CPU, nor on how many patterns were rendered in one pass. With AVX2
// (chosen when the program starts) 8 entries at a time, by gathers. Every j must index
// radiance (ForwardModel checks a row's steps when it loads them from a file).
double RowProduct(std::span<const TransportEntry> row, uint32_t first, const float* radiance);
double RowProductScalar(std::span<const TransportEntry> row, uint32_t first, const float* radiance);

// The row's products with kRowProductPatterns radiance images in one pass over its entries
// (which are most of a product's cost: a full-resolution transport is ~0.4 GB):
// radiance_interleaved[kRowProductPatterns * j + i] is image i's radiance at projector pixel j.
// out[i] equals RowProduct(row, first, image i) bit for bit. AVX2 when the CPU has it.
inline constexpr int kRowProductPatterns = 8;
void RowProducts(std::span<const TransportEntry> row, uint32_t first,
                 const float* radiance_interleaved, double out[kRowProductPatterns]);
void RowProductsScalar(std::span<const TransportEntry> row, uint32_t first,
                       const float* radiance_interleaved, double out[kRowProductPatterns]);

}  // namespace zbrdf
