// Tests of the stream buffer of cellform's standard output and error (app/escaping_buf.h).
#include "app/escaping_buf.h"

#include <catch2/catch.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace {
/// Records each piece written to it (what a write(2) each would be on an unbuffered stderr).
class Recorder : public std::streambuf {
 public:
  std::vector<std::string> pieces;
  std::string all() const {
    std::string s;
    for (const std::string& p : pieces) s += p;
    return s;
  }

 protected:
  int_type overflow(int_type ch) override {
    if (!traits_type::eq_int_type(ch, traits_type::eof())) pieces.emplace_back(1, traits_type::to_char_type(ch));
    return traits_type::not_eof(ch);
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    pieces.emplace_back(s, static_cast<std::size_t>(n));
    return n;
  }
};
}  // namespace

TEST_CASE("standard error passes each message on in one piece, its control bytes escaped", "[cli]") {
  Recorder to;
  {
    cellform::app::EscapingBuf buf(&to);
    std::ostream err(&buf);
    err.setf(std::ios::unitbuf);  // as main's err
    err << std::string("script: cell 12 at 0.5\n");
    REQUIRE(to.pieces.size() == 1);  // one write a line (it was one a character)
    CHECK(to.pieces[0] == "script: cell 12 at 0.5\n");
    err << "name \x1b[2J\x7f\ttab\r";
    REQUIRE(to.pieces.size() == 2);
    CHECK(to.pieces[1] == "name \\x1b[2J\\x7f\ttab\r");  // a name cannot clear the screen
    // a message longer than the buffer: all of it, in order
    const std::string long_line(10000, 'x');
    err << long_line << "\n";
    CHECK(to.all() == "script: cell 12 at 0.5\nname \\x1b[2J\\x7f\ttab\r" + long_line + "\n");
    // not flushed: passed on when the buffer goes
    err.unsetf(std::ios::unitbuf);
    err << "last";
    CHECK(to.all().find("last") == std::string::npos);
  }
  CHECK(to.all().substr(to.all().size() - 4) == "last");
}
