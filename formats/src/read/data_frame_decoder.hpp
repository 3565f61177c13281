// The worker side of the container reader: one data frame decompressed
// and parsed into pieces, its text into the record hash.
#pragma once

#include <cstdint>
#include <string>

#include "read/pipelined_reader.hpp"
#include "read/record_hash_chain.hpp"

namespace nodetrace::formats::detail {

// Pieces of a data frame: records per piece handed over, and pieces waiting
// per frame. The next frame's worker decodes ahead only as far as its
// pieces may wait: with 2 the two workers took turns (cachesim on the BART
// Kitchen trace 114% CPU use, 0.84-1.07 s; 21 MB), with 32 they overlap
// (165%, 0.49-0.68 s, as zstd -dc; 40-43 MB): the memory buys the second core.
// With the record hash, what a worker decodes ahead is text it must hold
// for the hash (record_hash_chain.hpp): with 8 pieces `tracetool verify` of
// that trace took 1.2-1.3x the CPU of `zstd -t` and 1.1-1.2x its wall time,
// with 32 1.45-1.6x and 0.85-0.9x (medians of runs on a loaded machine).
inline constexpr std::size_t kPiecesWaitingHashed = 8;
// Frames whose zstd window is larger than this (archives) are decoded one
// at a time, so only one such window is held.
inline constexpr std::uint64_t kSmallWindow = 8u << 20;

// Decodes a data frame into `stream` once `earlier` (the previous frame with
// a large window, if this one has one too) is done, then closes it. A frame
// that does not end whole ends the record hash's chain.
void decode_into(const std::string& frame, ParseSettings settings, RecordHashChain* hash, std::uint64_t hash_frame,
                 Stock& stock, PieceStream& stream, PieceStream* earlier);

}  // namespace nodetrace::formats::detail
