// The path tracer's low-discrepancy numbers (--sampler sobol): in each pixel
// and for each dimension, the sample numbers 0 .. spp - 1 are permuted by a
// hash (Kensler's "Correlated Multi-Jittered Sampling", 2013, cycle-walking
// permutation), and the permuted number indexes the first (van der Corput)
// or second dimension of the Sobol sequence, a (0, 2)-sequence, whose bits
// are then Owen-scrambled by a hash (Burley, "Practical Hash-based Owen
// Scrambling", JCGT 2020). The two numbers of a 2D pair (a direction, a point
// on an emitter, a point in the pixel) share the permuted index, so each
// pair is a scrambled (0, 2)-sequence in the pixel. pbrt-v4 calls this
// padding, as its PaddedSobolSampler does (its ZSobolSampler adds an
// ordering of pixels along a Morton curve, for blue-noise error, not lower
// error per pixel). Every number is a function of (frame, pixel, sample,
// bounce, dimension, spp): counter-based, as the independent numbers are.
// Internal header.
#pragma once

#include <array>
#include <cstdint>

namespace nodetrace::tracer::detail {

inline std::uint32_t reverse_bits(std::uint32_t v) {
  v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
  v = ((v >> 8) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8);
  return (v >> 16) | (v << 16);
}

// Point `index` of the Sobol sequence's dimension 0 (van der Corput) or 1
// (generator matrix: Pascal's triangle mod 2), as a 32-bit fraction with its
// bits reversed (bit 0 the fraction's first): the form Owen scrambling works
// on, so neither is reversed twice.
// Dimension 1 is the XOR of the matrix's columns of the index's set bits,
// read a byte at a time from a table of each byte's 256 XORs (no branch per
// bit, which a random index mispredicts half the time).
inline constexpr auto kSobolDimension1ByByte = [] {
  std::array<std::array<std::uint32_t, 256>, 4> table{};
  std::uint32_t column = 1;  // the column of index bit 0, reversed
  for (int bit = 0; bit < 32; ++bit, column ^= column << 1) {
    for (std::uint32_t value = 0; value < 256; ++value) {
      if (value >> (bit % 8) & 1) table[bit / 8][value] ^= column;
    }
  }
  return table;
}();

inline std::uint32_t sobol_bits_reversed(std::uint32_t index, int dimension) {
  if (dimension == 0) return index;
  const auto& t = kSobolDimension1ByByte;
  return t[0][index & 0xffu] ^ t[1][index >> 8 & 0xffu] ^ t[2][index >> 16 & 0xffu] ^ t[3][index >> 24];
}

// The same point as a 32-bit fraction.
inline std::uint32_t sobol_bits(std::uint32_t index, int dimension) {
  return reverse_bits(sobol_bits_reversed(index, dimension));
}

// Nested uniform scrambling of a 32-bit fraction given with its bits
// reversed, approximated by Burley's hash (each bit flipped by a hash of the
// bits above it); returns the scrambled fraction, not reversed.
inline std::uint32_t owen_scramble_reversed(std::uint32_t v, std::uint32_t seed) {
  v += seed;
  v ^= v * 0x6c50b47cu;
  v ^= v * 0xb82f1e52u;
  v ^= v * 0xc7afe638u;
  v ^= v * 0x8d22f6e6u;
  return reverse_bits(v);
}

// Point `index` of Sobol dimension 0 or 1, Owen-scrambled by `seed`.
inline std::uint32_t scrambled_sobol(std::uint32_t index, int dimension, std::uint32_t seed) {
  return owen_scramble_reversed(sobol_bits_reversed(index, dimension), seed);
}

// A permutation of 0 .. n - 1 chosen by `seed`: element i (Kensler 2013).
inline std::uint32_t permuted(std::uint32_t i, std::uint32_t n, std::uint32_t seed) {
  if (n <= 1) return 0;
  std::uint32_t w = n - 1;
  w |= w >> 1, w |= w >> 2, w |= w >> 4, w |= w >> 8, w |= w >> 16;
  do {
    i ^= seed;
    i *= 0xe170893du;
    i ^= seed >> 16;
    i ^= (i & w) >> 4;
    i ^= seed >> 8;
    i *= 0x0929eb3fu;
    i ^= seed >> 23;
    i ^= (i & w) >> 1;
    i *= 1 | seed >> 27;
    i *= 0x6935fa69u;
    i ^= (i & w) >> 11;
    i *= 0x74dcb303u;
    i ^= (i & w) >> 2;
    i *= 0x9e501cc3u;
    i ^= (i & w) >> 2;
    i *= 0xc860a3dfu;
    i &= w;
    i ^= i >> 5;
  } while (i >= n);
  return (i + seed) % n;
}

}  // namespace nodetrace::tracer::detail
