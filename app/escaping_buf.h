// The stream buffer of cellform's standard output and error (app/main.cpp).
#pragma once

#include <atomic>
#include <streambuf>
#include <string>

#include "core/errors.h"

namespace cellform::app {

/// What goes to the terminal with its control bytes escaped (\x1b, ...), but for line feeds, tabs and the
/// carriage returns of progress lines: a name read from a damaged file cannot clear the screen. Buffered,
/// and passed on in one piece at every flush (main's err flushes after each <<): std::cerr has no buffer of
/// its own, and a write per character made a script printing a line per cell 17 to 40 times slower and mixed
/// the lines of runs sharing a log.
class EscapingBuf : public std::streambuf {
 public:
  explicit EscapingBuf(std::streambuf* to) : to_(to) { setp(buf_, buf_ + sizeof buf_); }
  ~EscapingBuf() override { pass_on(); }
  /// Keeps `*flag` saying whether what was passed on so far ends a line (for a signal handler's message: it
  /// breaks a half-written line, and only such a line, first).
  void track_line_start(std::atomic<bool>* flag) { line_start_ = flag; }

 protected:
  int_type overflow(int_type ch) override {
    if (!pass_on()) return traits_type::eof();
    if (traits_type::eq_int_type(ch, traits_type::eof())) return traits_type::not_eof(ch);
    *pptr() = traits_type::to_char_type(ch);
    pbump(1);
    return ch;
  }
  int sync() override { return pass_on() && to_->pubsync() == 0 ? 0 : -1; }

 private:
  /// Escapes what the buffer holds and writes it on at once.
  bool pass_on() {
    const std::size_t n = static_cast<std::size_t>(pptr() - pbase());
    if (n == 0) return true;
    std::string text;
    text.reserve(n);
    for (std::size_t k = 0; k < n; ++k) {
      const auto c = static_cast<unsigned char>(buf_[k]);
      if ((c >= 0x20 && c != 0x7f) || c == '\n' || c == '\r' || c == '\t')
        text.push_back(static_cast<char>(c));
      else
        text += cellform::core::printable(std::string(1, static_cast<char>(c)));
    }
    setp(buf_, buf_ + sizeof buf_);
    const bool written =
        to_->sputn(text.data(), static_cast<std::streamsize>(text.size())) == static_cast<std::streamsize>(text.size());
    if (line_start_) line_start_->store(text.back() == '\n');
    return written;
  }

  std::streambuf* to_;
  std::atomic<bool>* line_start_ = nullptr;
  char buf_[4096];
};

}  // namespace cellform::app
