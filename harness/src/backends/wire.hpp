// wire.hpp: the byte protocol between the harness and its GL worker processes.
//
// Implements: framing over file descriptors (pipes) and the (de)serialisation of the two
// messages that cross them, a refraster::DrawList (request) and a harness::RenderResult
// (reply: the image and, for a 4x target, every sample). A frame is a 12-byte header, uint32 type
// then uint64 payload length, followed by the payload. Numbers are little-endian; floats travel as
// their bit patterns, so a DrawList arrives bit for bit as it was sent. A DrawList's textures
// travel after its draws, every level's texels as one block of bytes, and each draw's texture
// state after the rest of its state.
//
// Reading and writing are incremental (FrameReader/FrameWriter do one read(2)/write(2) per
// call) so that a caller can put poll(2) with a deadline between calls; blocking helpers
// are built on the same classes. EINTR is retried, short reads and writes are resumed, and
// every decode checks lengths before it touches memory: a truncated or corrupt stream throws
// WireError, never reads past a buffer. A texture level whose bytes are not width * height * 4
// is corrupt too, since the worker gives them to glTexImage2D as they are.
//
// Deliberately does not: know anything about GL, processes, signals or timeouts, nor
// version the protocol (both ends are always built from the same tree).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/backend.hpp"
#include "refraster/draw.hpp"
#include "refraster/error.hpp"

namespace harness::wire {

enum class FrameType : std::uint32_t {
    Hello = 1,   // worker -> harness once at start-up: a reply without image (status, provenance)
    Render = 2,  // harness -> worker: payload is an encoded DrawList
    Reply = 3,   // worker -> harness: payload is an encoded RenderResult
    RenderOwners = 4,  // harness -> worker: as Render, plus the primitive-owner attachment
    // Test hooks: the worker aborts, or sleeps forever, on receipt. Empty payload.
    Crash = 0x7e01,
    Hang = 0x7e02,
};

inline constexpr std::size_t kHeaderBytes = 12;
// Larger than any legal message (67M rgba32f samples with depth and owners, plus their
// resolved image, come to about 2 GiB), and small enough that a corrupt length is refused
// rather than allocated.
inline constexpr std::uint64_t kMaxPayloadBytes = std::uint64_t{4} << 30;

// A protocol or I/O failure. `error_number()` is the errno of a failed system call, 0 when the
// stream itself was bad (truncated, oversized, undecodable).
// A backend failure: the worker at the other end broke the protocol or went away.
class WireError : public refraster::Error {
  public:
    explicit WireError(const std::string& message, int error_number = 0)
        : refraster::Error(refraster::ExitClass::BackendFailure, message), errno_(error_number) {}
    int error_number() const { return errno_; }

  private:
    int errno_;
};

struct Frame {
    std::uint32_t type = 0;  // a FrameType value, kept raw so that an unknown type is reportable
    std::vector<std::uint8_t> payload;
};

// Message bodies. Every decode consumes its whole input and throws WireError otherwise.
std::vector<std::uint8_t> encode_draw_list(const refraster::DrawList& list);
refraster::DrawList decode_draw_list(std::span<const std::uint8_t> payload);
std::vector<std::uint8_t> encode_result(const harness::RenderResult& result);
harness::RenderResult decode_result(std::span<const std::uint8_t> payload);
// The same, for a result (or payload) the caller gives up: its pages are given back a block at
// a time as they are copied, so that an image of a gigabyte is not held twice. The bytes are
// the same.
std::vector<std::uint8_t> encode_result(harness::RenderResult&& result);
harness::RenderResult decode_result(std::vector<std::uint8_t>&& payload);

// Collects one frame from a file descriptor, one read(2) per call.
class FrameReader {
  public:
    enum class Progress : std::uint8_t {
        NeedMore,  // nothing complete yet (also after EAGAIN on a non-blocking fd)
        Complete,  // take() returns the frame
        Eof,       // end of stream exactly between two frames
    };

    // Throws WireError on a read error, on end of stream inside a frame, or on a header whose
    // length exceeds kMaxPayloadBytes.
    Progress read_some(int fd);
    // The completed frame; the reader is then ready for the next one.
    Frame take();

  private:
    std::uint8_t header_[kHeaderBytes] = {};
    std::size_t header_got_ = 0;
    std::uint64_t length_ = 0;
    std::uint64_t payload_got_ = 0;
    Frame frame_;
    bool complete_ = false;
};

// Sends one frame, one write(2) per call.
class FrameWriter {
  public:
    FrameWriter(FrameType type, std::vector<std::uint8_t> payload);
    // True once everything is written. A non-blocking fd that is full makes no progress and
    // returns false. Throws WireError on a write error (EPIPE when the reader has gone; the
    // caller must ignore SIGPIPE to see it).
    bool write_some(int fd);

  private:
    std::uint8_t header_[kHeaderBytes] = {};
    std::vector<std::uint8_t> payload_;
    std::uint64_t written_ = 0;  // header and payload bytes together
};

// Blocking helpers (they wait with poll(2) if the fd happens to be non-blocking).
// read_frame returns nullopt on a clean end of stream between frames.
std::optional<Frame> read_frame(int fd);
void write_frame(int fd, FrameType type, std::vector<std::uint8_t> payload);

}  // namespace harness::wire
