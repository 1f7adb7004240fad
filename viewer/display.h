// The display path of epi-viewer: linear frames to RGBA8 (DisplayEncoder, display_encoder.h, on the frame thread),
// three persistently mapped pixel buffers the frame thread writes into (PixelRing), and the
// texture the window blits (FrameTexture). Only app.cpp includes this; it needs a GL context.
#pragma once

#define GL_GLEXT_PROTOTYPES
#define GLFW_INCLUDE_GLEXT
#include <GLFW/glfw3.h>

#include <array>
#include <cstdint>
#include <mutex>

#include "display_encoder.h"
#include "image/image.h"

namespace epi::viewer {

// The newest frame on screen: two pixel buffer objects in turn feed one texture, which is blitted
// to the window (no shader: "texture upload only").
class FrameTexture {
 public:
  FrameTexture() {
    glGenTextures(1, &texture_);
    glGenBuffers(2, pbo_);
    glGenFramebuffers(1, &framebuffer_);
  }
  ~FrameTexture() {
    glDeleteFramebuffers(1, &framebuffer_);
    glDeleteBuffers(2, pbo_);
    glDeleteTextures(1, &texture_);
  }
  // Maps the next PBO for a width x height frame: the caller writes its RGBA8 pixels there, then
  // calls finish_upload().
  uint32_t* begin_upload(int width, int height) {
    const size_t bytes = size_t(width) * size_t(height) * 4;
    resize(width, height);
    next_ = 1 - next_;
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, pbo_[next_]);
    glBufferData(GL_PIXEL_UNPACK_BUFFER, GLsizeiptr(bytes), nullptr, GL_STREAM_DRAW);  // orphan: no wait on the GPU
    mapped_ = glMapBufferRange(GL_PIXEL_UNPACK_BUFFER, 0, GLsizeiptr(bytes), GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT);
    if (!mapped_) glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    return static_cast<uint32_t*>(mapped_);
  }
  // The texture takes a width x height frame from a pixel buffer the frame thread filled.
  void upload_from(GLuint buffer, int width, int height) {
    resize(width, height);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, buffer);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
  }
  void resize(int width, int height) {
    if (width != width_ || height != height_) {
      glBindTexture(GL_TEXTURE_2D, texture_);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
      glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_, 0);
      glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
      width_ = width, height_ = height;
    }
  }
  // Unmaps the PBO and has the texture take its pixels.
  void finish_upload() {
    if (!mapped_) return;
    glUnmapBuffer(GL_PIXEL_UNPACK_BUFFER);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    mapped_ = nullptr;
  }
  // Draws the texture over the window, y down (the image's first row at the top): pixel for
  // pixel, or scaled up bilinearly where the renderer renders fewer pixels (--render-scale).
  void draw(int window_width, int window_height) const {
    if (width_ == 0) return;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    const bool same_size = width_ == window_width && height_ == window_height;
    glBlitFramebuffer(0, 0, width_, height_, 0, window_height, window_width, 0, GL_COLOR_BUFFER_BIT, same_size ? GL_NEAREST : GL_LINEAR);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  GLuint texture_ = 0, framebuffer_ = 0, pbo_[2] = {0, 0};
  int width_ = 0, height_ = 0, next_ = 0;
  void* mapped_ = nullptr;
};

// Three persistently mapped pixel buffers that the frame thread writes each frame's RGBA8 into
// directly (DisplayEncoder output), so the window thread only has the texture take them: no copy
// on the window thread. A slot is free, being written (frame thread), ready (the newest frame's
// pixels), or in use by GL (window thread, until its fence signals). Window-thread calls need the
// GL context; acquire() and ready() are the frame thread's and never call GL. Where the driver
// lacks GL_ARB_buffer_storage, acquire() returns nullptr and frames take the copying path.
class PixelRing {
 public:
  explicit PixelRing(bool supported) : supported_(supported) {}
  ~PixelRing() {  // window thread, after the session (the frame thread) has stopped
    for (Slot& s : slots_) release(s);
  }

  // Frame thread: a free slot for a width x height frame, marked as being written, and its tag;
  // nullptr when none is free or the slots have another size (the window thread then makes
  // slots of this size).
  uint32_t* acquire(int width, int height, int64_t& tag) {
    std::lock_guard lock(mutex_);
    if (!supported_) return nullptr;
    if (width != width_ || height != height_) {
      want_width_ = width, want_height_ = height;
      return nullptr;
    }
    for (int k = 0; k < kSlots; ++k) {
      Slot& s = slots_[k];
      if (s.state != State::free || !s.pixels) continue;
      s.state = State::writing;
      ++s.generation;
      tag = int64_t(s.generation) * kSlots + k;
      return s.pixels;
    }
    return nullptr;
  }
  // Frame thread: the slot holds a whole frame; an older frame never taken is dropped.
  void ready(int64_t tag) {
    std::lock_guard lock(mutex_);
    for (Slot& s : slots_)
      if (s.state == State::ready) s.state = State::free;
    slots_[tag % kSlots].state = State::ready;
  }

  // Window thread: the texture takes the tagged frame if its slot still holds it (a ready slot,
  // or with `again` a free one: the benchmark's repeated upload of the last frame). Returns
  // whether it did.
  bool upload(int64_t tag, FrameTexture& texture, int width, int height, bool again = false) {
    Slot& s = slots_[tag % kSlots];
    {
      std::lock_guard lock(mutex_);
      const bool holds = s.generation == uint64_t(tag / kSlots) && (s.state == State::ready || (again && s.state == State::free));
      if (!holds) return false;
      s.state = State::in_use;
    }
    texture.upload_from(s.buffer, width, height);
    GLsync fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    std::lock_guard lock(mutex_);
    s.fence = fence;
    return true;
  }
  // Window thread, once per window frame: frees the slots GL is done with; makes slots of the
  // size the frame thread asked for once none is being written or used.
  void maintain() {
    std::lock_guard lock(mutex_);
    for (Slot& s : slots_)
      if (s.state == State::in_use && s.fence && glClientWaitSync(s.fence, 0, 0) != GL_TIMEOUT_EXPIRED)
        glDeleteSync(s.fence), s.fence = nullptr, s.state = State::free;
    if (!supported_ || (want_width_ == width_ && want_height_ == height_)) return;
    for (const Slot& s : slots_)
      if (s.state == State::writing || s.state == State::in_use) return;
    const GLsizeiptr bytes = GLsizeiptr(want_width_) * want_height_ * 4;
    const GLbitfield flags = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
    for (Slot& s : slots_) {
      release(s);
      glGenBuffers(1, &s.buffer);
      glBindBuffer(GL_PIXEL_UNPACK_BUFFER, s.buffer);
      glBufferStorage(GL_PIXEL_UNPACK_BUFFER, bytes, nullptr, flags);
      s.pixels = static_cast<uint32_t*>(glMapBufferRange(GL_PIXEL_UNPACK_BUFFER, 0, bytes, flags));
      s.state = State::free;
      ++s.generation;  // tags of the old slots no longer match
    }
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    width_ = want_width_, height_ = want_height_;
  }

 private:
  static constexpr int kSlots = 3;
  enum class State { free, writing, ready, in_use };
  struct Slot {
    GLuint buffer = 0;
    uint32_t* pixels = nullptr;
    State state = State::free;
    uint64_t generation = 0;
    GLsync fence = nullptr;
  };
  static void release(Slot& s) {
    if (s.fence) glDeleteSync(s.fence), s.fence = nullptr;
    if (s.buffer) glDeleteBuffers(1, &s.buffer), s.buffer = 0;  // unmaps
    s.pixels = nullptr;
  }
  const bool supported_;
  std::mutex mutex_;
  std::array<Slot, kSlots> slots_;
  int width_ = 0, height_ = 0, want_width_ = 0, want_height_ = 0;
};

}  // namespace epi::viewer
