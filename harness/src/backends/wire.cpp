// wire.cpp: see wire.hpp. Both ends of a pipe run on the same host, so multi-byte values are
// copied in native order, and the build refuses a big-endian host rather than pretend.
#include "wire.hpp"

#include <poll.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

namespace harness::wire {

static_assert(std::endian::native == std::endian::little,
              "the wire format is little-endian and copied natively");

namespace {

// Blocks of this many bytes are copied between a message and its images, so that a side that
// is given up can give its pages back as the copy goes (release_pages).
constexpr std::size_t kCopyBlock = std::size_t{16} << 20;

// Gives the whole pages inside [begin, end) back to the system: memory its owner never reads
// again (it would read zeros). At the target limit an image is over a gigabyte, and without
// this the encoder or decoder would hold it twice.
void release_pages(const void* begin, const void* end) {
    static const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
    const std::uintptr_t from = (reinterpret_cast<std::uintptr_t>(begin) + page - 1) & ~(page - 1);
    const std::uintptr_t to = reinterpret_cast<std::uintptr_t>(end) & ~(page - 1);
    if (to > from) ::madvise(reinterpret_cast<void*>(from), to - from, MADV_DONTNEED);
}

class Encoder {
  public:
    template <typename T>
    void put(T v) {
        static_assert(std::is_trivially_copyable_v<T>);
        const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
        out_.insert(out_.end(), p, p + sizeof(T));
    }
    void u8(std::uint8_t v) { put(v); }
    void boolean(bool v) { put(static_cast<std::uint8_t>(v ? 1 : 0)); }
    void u32(std::uint32_t v) { put(v); }
    void i32(std::int32_t v) { put(v); }
    void u64(std::uint64_t v) { put(v); }
    void f32(float v) { put(std::bit_cast<std::uint32_t>(v)); }
    void f64(double v) { put(std::bit_cast<std::uint64_t>(v)); }
    template <typename E>
    void enumeration(E v) {
        put(static_cast<std::underlying_type_t<E>>(v));
    }
    void string(const std::string& s) {
        u64(s.size());
        out_.insert(out_.end(), s.begin(), s.end());
    }
    // A counted array of trivially copyable elements, copied as one block; with `release`,
    // a block at a time, each block's pages of `v` given back once copied (v is then read
    // as zeros: the caller is done with it).
    template <typename T, typename A>
    void array(const std::vector<T, A>& v, bool release = false) {
        static_assert(std::is_trivially_copyable_v<T>);
        u64(v.size());
        const auto* p = reinterpret_cast<const std::uint8_t*>(v.data());
        const std::size_t n = v.size() * sizeof(T);
        for (std::size_t off = 0; off < n; off += kCopyBlock) {
            const std::size_t m = std::min(kCopyBlock, n - off);
            out_.insert(out_.end(), p + off, p + off + m);
            if (release) release_pages(p + off, p + off + m);
        }
    }
    void reserve(std::size_t n) { out_.reserve(n); }
    std::vector<std::uint8_t> take() { return std::move(out_); }

  private:
    std::vector<std::uint8_t> out_;
};

class Decoder {
  public:
    explicit Decoder(std::span<const std::uint8_t> in) : in_(in) {}
    // A decoder that gives the pages of `in` back as its arrays are copied out (in is then
    // read as zeros: the caller is done with it).
    Decoder(std::span<std::uint8_t> in, bool release) : in_(in), release_(release) {}

    template <typename T>
    T get() {
        static_assert(std::is_trivially_copyable_v<T>);
        need(sizeof(T));
        T v;
        std::memcpy(&v, in_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        return v;
    }
    std::uint8_t u8() { return get<std::uint8_t>(); }
    bool boolean() {
        const std::uint8_t v = u8();
        if (v > 1) fail("boolean out of range");
        return v == 1;
    }
    std::uint32_t u32() { return get<std::uint32_t>(); }
    std::int32_t i32() { return get<std::int32_t>(); }
    std::uint64_t u64() { return get<std::uint64_t>(); }
    float f32() { return std::bit_cast<float>(get<std::uint32_t>()); }
    double f64() { return std::bit_cast<double>(get<std::uint64_t>()); }
    // An enum whose values run 0..last; anything else is a corrupt stream.
    template <typename E>
    E enumeration(E last) {
        using U = std::underlying_type_t<E>;
        const U raw = get<U>();
        if (raw > static_cast<U>(last)) fail("enum value out of range");
        return static_cast<E>(raw);
    }
    std::string string() {
        const std::size_t n = count(1);
        std::string s(reinterpret_cast<const char*>(in_.data() + pos_), n);
        pos_ += n;
        return s;
    }
    // A counted byte block, copied once (no zero fill first).
    std::vector<std::uint8_t> bytes() {
        const std::size_t n = count(1);
        const auto first = in_.begin() + static_cast<std::ptrdiff_t>(pos_);
        std::vector<std::uint8_t> v(first, first + static_cast<std::ptrdiff_t>(n));
        pos_ += n;
        return v;
    }
    template <typename T, typename A = std::allocator<T>>
    std::vector<T, A> array() {
        static_assert(std::is_trivially_copyable_v<T>);
        const std::size_t n = count(sizeof(T));
        std::vector<T, A> v;
        v.reserve(n);
        // A block at a time, so that only the block being copied is held twice.
        constexpr std::size_t kBlock = kCopyBlock / sizeof(T);
        for (std::size_t done = 0; done < n; done += kBlock) {
            const std::size_t m = std::min(kBlock, n - done);
            v.resize(done + m);
            const std::uint8_t* from = in_.data() + pos_ + done * sizeof(T);
            std::memcpy(v.data() + done, from, m * sizeof(T));
            if (release_) release_pages(from, from + m * sizeof(T));
        }
        pos_ += n * sizeof(T);
        return v;
    }
    // An element count, checked against what is left so that a corrupt count cannot make the
    // decoder allocate more than the payload could hold.
    std::size_t count(std::size_t element_bytes) {
        const std::uint64_t n = u64();
        const std::size_t left = in_.size() - pos_;
        if (element_bytes != 0 && n > left / element_bytes) fail("count exceeds payload");
        return static_cast<std::size_t>(n);
    }
    void finish() const {
        if (pos_ != in_.size()) fail("trailing bytes after message");
    }
    [[noreturn]] void fail(const char* what) const {
        throw WireError(std::string("corrupt message at byte ") + std::to_string(pos_) + ": " +
                        what);
    }

  private:
    void need(std::size_t n) const {
        if (in_.size() - pos_ < n) fail("truncated");
    }
    std::span<const std::uint8_t> in_;
    std::size_t pos_ = 0;
    bool release_ = false;
};

void put_rect(Encoder& e, const refraster::Rect& r) {
    e.i32(r.x);
    e.i32(r.y);
    e.i32(r.width);
    e.i32(r.height);
}

refraster::Rect get_rect(Decoder& d) {
    refraster::Rect r;
    r.x = d.i32();
    r.y = d.i32();
    r.width = d.i32();
    r.height = d.i32();
    return r;
}

void put_state(Encoder& e, const refraster::DrawState& s) {
    put_rect(e, s.viewport);
    e.f32(s.depth_near);
    e.f32(s.depth_far);
    e.boolean(s.scissor.has_value());
    if (s.scissor) put_rect(e, *s.scissor);
    e.enumeration(s.cull);
    e.enumeration(s.front_face);
    e.boolean(s.depth_test.has_value());
    if (s.depth_test) e.enumeration(*s.depth_test);
    e.boolean(s.depth_write);
    e.enumeration(s.shade);
    e.enumeration(s.provoking_vertex);
    e.enumeration(s.polygon_mode);
    e.boolean(s.polygon_offset.has_value());
    if (s.polygon_offset) {
        e.f32(s.polygon_offset->factor);
        e.f32(s.polygon_offset->units);
    }
    e.f32(s.line_width);
    e.f32(s.point_size);
    e.enumeration(s.blend);
    e.boolean(s.multisample);
    e.boolean(s.texture.has_value());
    if (s.texture) {
        const auto& t = *s.texture;
        e.u32(t.texture);
        e.enumeration(t.min_filter);
        e.enumeration(t.mag_filter);
        e.enumeration(t.wrap_s);
        e.enumeration(t.wrap_t);
        for (float c : t.border_color) e.f32(c);
        e.enumeration(t.env);
        e.boolean(t.coord_replace);
        e.enumeration(t.point_coord_origin);
    }
    e.boolean(s.fill_rule.has_value());
    if (s.fill_rule) e.enumeration(*s.fill_rule);
}

refraster::DrawState get_state(Decoder& d) {
    using namespace refraster;
    DrawState s;
    s.viewport = get_rect(d);
    s.depth_near = d.f32();
    s.depth_far = d.f32();
    if (d.boolean()) s.scissor = get_rect(d);
    s.cull = d.enumeration(CullMode::FrontAndBack);
    s.front_face = d.enumeration(FrontFace::Cw);
    if (d.boolean()) s.depth_test = d.enumeration(CompareFunc::Always);
    s.depth_write = d.boolean();
    s.shade = d.enumeration(ShadeModel::NoPerspective);
    s.provoking_vertex = d.enumeration(ProvokingVertex::First);
    s.polygon_mode = d.enumeration(PolygonMode::Point);
    if (d.boolean()) {
        PolygonOffset o;
        o.factor = d.f32();
        o.units = d.f32();
        s.polygon_offset = o;
    }
    s.line_width = d.f32();
    s.point_size = d.f32();
    s.blend = d.enumeration(BlendPreset::Add);
    s.multisample = d.boolean();
    if (d.boolean()) {
        TextureState t;
        t.texture = d.u32();
        t.min_filter = d.enumeration(TextureFilter::LinearMipmapLinear);
        t.mag_filter = d.enumeration(TextureFilter::LinearMipmapLinear);
        t.wrap_s = d.enumeration(TextureWrap::ClampToBorder);
        t.wrap_t = d.enumeration(TextureWrap::ClampToBorder);
        for (float& c : t.border_color) c = d.f32();
        t.env = d.enumeration(TextureEnv::Replace);
        t.coord_replace = d.boolean();
        t.point_coord_origin = d.enumeration(PointCoordOrigin::LowerLeft);
        s.texture = t;
    }
    if (d.boolean()) s.fill_rule = d.enumeration(FillRule::NonZero);
    return s;
}

// A texture: the generate flag, then its levels, each its size and its texels as one block
// (a 4096x4096 level is 64 MiB: copied once each way, never converted).
void put_texture(Encoder& e, const refraster::Texture& t) {
    e.boolean(t.generate_mipmaps);
    e.u64(t.levels.size());
    for (const auto& level : t.levels) {
        e.u32(level.width);
        e.u32(level.height);
        e.array(level.rgba);
    }
}

refraster::Texture get_texture(Decoder& d) {
    refraster::Texture t;
    t.generate_mipmaps = d.boolean();
    // A level takes at least 16 bytes (two sizes and an empty block's count).
    const std::size_t levels = d.count(16);
    t.levels.reserve(levels);
    for (std::size_t i = 0; i < levels; ++i) {
        refraster::TextureImage level;
        level.width = d.u32();
        level.height = d.u32();
        level.rgba = d.bytes();
        // The GL worker hands the block to glTexImage2D, which reads width * height * 4 bytes.
        if (level.rgba.size() != std::uint64_t{level.width} * level.height * 4) {
            d.fail("texture level size does not match its texels");
        }
        t.levels.push_back(std::move(level));
    }
    return t;
}

void put_framebuffer(Encoder& e, const refraster::Framebuffer& fb, bool release) {
    e.u32(fb.width);
    e.u32(fb.height);
    e.enumeration(fb.color_format);
    e.enumeration(fb.depth_format);
    e.u32(fb.samples);
    e.array(fb.color8, release);
    e.array(fb.color32f, release);
    e.array(fb.depth, release);
    e.array(fb.owner, release);
}

refraster::Framebuffer get_framebuffer(Decoder& d) {
    refraster::Framebuffer fb;
    fb.width = d.u32();
    fb.height = d.u32();
    fb.color_format = d.enumeration(refraster::ColorFormat::Rgba32f);
    fb.depth_format = d.enumeration(refraster::DepthFormat::Z32f);
    fb.samples = d.u32();
    if (fb.samples != 1 && fb.samples != 4) d.fail("sample count other than 1 or 4");
    fb.color8 = d.array<std::uint8_t, refraster::PixelAllocator<std::uint8_t>>();
    fb.color32f = d.array<float, refraster::PixelAllocator<float>>();
    fb.depth = d.array<std::uint32_t, refraster::PixelAllocator<std::uint32_t>>();
    fb.owner = d.array<std::uint32_t>();
    return fb;
}

void put_header(std::uint8_t (&h)[kHeaderBytes], std::uint32_t type, std::uint64_t length) {
    std::memcpy(h, &type, 4);
    std::memcpy(h + 4, &length, 8);
}

// Waits until `fd` is ready for `events`; used only by the blocking helpers, for an fd that
// turned out to be non-blocking.
void wait_ready(int fd, short events) {
    pollfd p{fd, events, 0};
    while (::poll(&p, 1, -1) < 0) {
        if (errno != EINTR) throw WireError(std::string("poll: ") + std::strerror(errno), errno);
    }
}

}  // namespace

std::vector<std::uint8_t> encode_draw_list(const refraster::DrawList& list) {
    Encoder e;
    std::size_t estimate = 64;
    for (const auto& d : list.draws) {
        estimate += 128 + d.vertices.data.size() * 4 + (d.indices ? d.indices->size() * 4 : 0);
    }
    for (const auto& texture : list.textures) {
        estimate += 16;
        for (const auto& level : texture.levels) estimate += 16 + level.rgba.size();
    }
    e.reserve(estimate);

    const auto& t = list.target;
    e.u32(t.width);
    e.u32(t.height);
    e.enumeration(t.color);
    e.enumeration(t.depth);
    e.u32(t.samples);
    for (float c : list.clear.color) e.f32(c);
    e.f32(list.clear.depth);

    e.u64(list.draws.size());
    for (const auto& d : list.draws) {
        e.enumeration(d.primitive);
        put_state(e, d.state);
        e.u64(d.vertices.attributes.size());
        for (const auto& a : d.vertices.attributes) {
            e.string(a.name);
            e.u32(a.components);
        }
        e.array(d.vertices.data);
        e.boolean(d.indices.has_value());
        if (d.indices) e.array(*d.indices);
    }
    // The textures follow the draws, so that a list without any ends as it always did but
    // for their count.
    e.u64(list.textures.size());
    for (const auto& texture : list.textures) put_texture(e, texture);
    return e.take();
}

refraster::DrawList decode_draw_list(std::span<const std::uint8_t> payload) {
    using namespace refraster;
    Decoder d(payload);
    DrawList list;
    list.target.width = d.u32();
    list.target.height = d.u32();
    list.target.color = d.enumeration(ColorFormat::Rgba32f);
    list.target.depth = d.enumeration(DepthFormat::Z32f);
    list.target.samples = d.u32();
    for (float& c : list.clear.color) c = d.f32();
    list.clear.depth = d.f32();

    // Every encoded draw takes more than 32 bytes (about 60 for an empty one); the bound
    // only stops a corrupt count from reserving absurd memory.
    const std::size_t draws = d.count(32);
    list.draws.reserve(draws);
    for (std::size_t i = 0; i < draws; ++i) {
        Draw draw;
        draw.primitive = d.enumeration(PrimitiveType::Polygon);
        draw.state = get_state(d);
        const std::size_t attributes = d.count(12);
        for (std::size_t a = 0; a < attributes; ++a) {
            AttributeDesc desc;
            desc.name = d.string();
            desc.components = d.u32();
            draw.vertices.attributes.push_back(std::move(desc));
        }
        draw.vertices.data = d.array<float>();
        if (d.boolean()) draw.indices = d.array<std::uint32_t>();
        list.draws.push_back(std::move(draw));
    }
    // A texture takes at least 9 bytes (its flag and its level count).
    const std::size_t textures = d.count(9);
    list.textures.reserve(textures);
    for (std::size_t i = 0; i < textures; ++i) list.textures.push_back(get_texture(d));
    d.finish();
    return list;
}

namespace {

std::vector<std::uint8_t> encode_result(const harness::RenderResult& r, bool release) {
    Encoder e;
    const auto bytes = [](const refraster::Framebuffer& fb) {
        return fb.color8.size() + (fb.color32f.size() + fb.depth.size() + fb.owner.size()) * 4;
    };
    e.reserve(256 + r.message.size() + bytes(r.image) + bytes(r.samples));
    e.enumeration(r.status);
    e.string(r.message);
    put_framebuffer(e, r.image, release);
    put_framebuffer(e, r.samples, release);
    e.u64(r.provenance.size());
    for (const auto& [k, v] : r.provenance) {
        e.string(k);
        e.string(v);
    }
    e.f64(r.seconds);
    return e.take();
}

harness::RenderResult decode_result(Decoder& d) {
    harness::RenderResult r;
    r.status = d.enumeration(harness::RenderStatus::InternalError);
    r.message = d.string();
    r.image = get_framebuffer(d);
    r.samples = get_framebuffer(d);
    const std::size_t entries = d.count(16);
    for (std::size_t i = 0; i < entries; ++i) {
        std::string k = d.string();
        std::string v = d.string();
        r.provenance.insert_or_assign(std::move(k), std::move(v));
    }
    r.seconds = d.f64();
    d.finish();
    return r;
}

}  // namespace

std::vector<std::uint8_t> encode_result(const harness::RenderResult& r) {
    return encode_result(r, false);
}

std::vector<std::uint8_t> encode_result(harness::RenderResult&& r) {
    const harness::RenderResult given = std::move(r);
    return encode_result(given, true);
}

harness::RenderResult decode_result(std::span<const std::uint8_t> payload) {
    Decoder d(payload);
    return decode_result(d);
}

harness::RenderResult decode_result(std::vector<std::uint8_t>&& payload) {
    std::vector<std::uint8_t> given = std::move(payload);
    Decoder d(std::span<std::uint8_t>(given), true);
    return decode_result(d);
}

FrameReader::Progress FrameReader::read_some(int fd) {
    if (complete_) return Progress::Complete;
    std::uint8_t* dst = nullptr;
    std::size_t want = 0;
    if (header_got_ < kHeaderBytes) {
        dst = header_ + header_got_;
        want = kHeaderBytes - header_got_;
    } else {
        // The payload grows as it arrives: a corrupt length on a dying stream must not cost
        // its full size in memory before the truncation is noticed. Its whole length is
        // reserved at once (address space, which costs nothing until written), so that growing
        // never copies what has arrived.
        constexpr std::uint64_t kStep = std::uint64_t{64} << 20;
        if (frame_.payload.capacity() < length_)
            frame_.payload.reserve(static_cast<std::size_t>(length_));
        if (payload_got_ == frame_.payload.size()) {
            const std::uint64_t next = std::min(length_, payload_got_ + kStep);
            frame_.payload.resize(static_cast<std::size_t>(next));
        }
        dst = frame_.payload.data() + payload_got_;
        want = static_cast<std::size_t>(frame_.payload.size() - payload_got_);
    }
    want = std::min<std::size_t>(want, std::numeric_limits<ssize_t>::max());

    ssize_t n = 0;
    do {
        n = ::read(fd, dst, want);
    } while (n < 0 && errno == EINTR);
    if (n < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK) return Progress::NeedMore;
        throw WireError(std::string("read: ") + std::strerror(errno), errno);
    }
    if (n == 0) {
        if (header_got_ == 0) return Progress::Eof;
        throw WireError("stream truncated inside a frame");
    }

    const auto got = static_cast<std::size_t>(n);
    if (header_got_ < kHeaderBytes) {
        header_got_ += got;
        if (header_got_ < kHeaderBytes) return Progress::NeedMore;
        std::memcpy(&frame_.type, header_, 4);
        std::memcpy(&length_, header_ + 4, 8);
        if (length_ > kMaxPayloadBytes) {
            throw WireError("frame length " + std::to_string(length_) + " exceeds the limit");
        }
        payload_got_ = 0;
        frame_.payload.clear();
    } else {
        payload_got_ += got;
    }
    if (payload_got_ == length_) complete_ = true;
    return complete_ ? Progress::Complete : Progress::NeedMore;
}

Frame FrameReader::take() {
    if (!complete_) throw WireError("no complete frame to take");
    Frame f = std::move(frame_);
    frame_ = Frame{};
    header_got_ = 0;
    length_ = 0;
    payload_got_ = 0;
    complete_ = false;
    return f;
}

FrameWriter::FrameWriter(FrameType type, std::vector<std::uint8_t> payload)
    : payload_(std::move(payload)) {
    if (payload_.size() > kMaxPayloadBytes) {
        throw WireError("payload of " + std::to_string(payload_.size()) +
                        " bytes exceeds the limit");
    }
    put_header(header_, static_cast<std::uint32_t>(type), payload_.size());
}

bool FrameWriter::write_some(int fd) {
    const std::uint64_t total = kHeaderBytes + payload_.size();
    if (written_ == total) return true;
    const std::uint8_t* src = nullptr;
    std::size_t want = 0;
    if (written_ < kHeaderBytes) {
        src = header_ + written_;
        want = kHeaderBytes - static_cast<std::size_t>(written_);
    } else {
        const auto off = static_cast<std::size_t>(written_ - kHeaderBytes);
        src = payload_.data() + off;
        want = payload_.size() - off;
    }
    want = std::min<std::size_t>(want, std::numeric_limits<ssize_t>::max());

    ssize_t n = 0;
    do {
        n = ::write(fd, src, want);
    } while (n < 0 && errno == EINTR);
    if (n < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK) return false;
        throw WireError(std::string("write: ") + std::strerror(errno), errno);
    }
    written_ += static_cast<std::uint64_t>(n);
    return written_ == total;
}

std::optional<Frame> read_frame(int fd) {
    FrameReader reader;
    for (;;) {
        switch (reader.read_some(fd)) {
            case FrameReader::Progress::Complete:
                return reader.take();
            case FrameReader::Progress::Eof:
                return std::nullopt;
            case FrameReader::Progress::NeedMore:
                break;
        }
        // NeedMore after a partial read is normal; after EAGAIN it needs a wait. Polling a
        // blocking fd that has data returns at once, so waiting unconditionally is harmless.
        wait_ready(fd, POLLIN);
    }
}

void write_frame(int fd, FrameType type, std::vector<std::uint8_t> payload) {
    FrameWriter writer(type, std::move(payload));
    while (!writer.write_some(fd)) wait_ready(fd, POLLOUT);
}

}  // namespace harness::wire
