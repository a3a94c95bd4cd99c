// Errors keep the whole message, and text shown on a terminal is escaped: a NUL byte quoted from
// input neither ends a message nor reaches the terminal raw.
#include "core/error.h"

#include <gtest/gtest.h>

#include <string>

namespace stsv {
namespace {

const std::string WITH_NUL("a\0b.png: does not exist", 23);

TEST(Error, MessageKeepsTheTextPastANulByte) {
    const InputError e(std::string("scene/", 6) + WITH_NUL, "cannot open");
    EXPECT_EQ(e.message(), "scene/" + WITH_NUL + ": cannot open");
    EXPECT_EQ(std::string(e.what()), "scene/a") << "what() is a C string: it ends at the NUL";
    // Copies share the message (copying an exception must not throw).
    const Error copy = e; // NOLINT(performance-unnecessary-copy-initialization): the copy is the test
    EXPECT_EQ(copy.message(), e.message());
    const UsageError usage("--set '" + WITH_NUL + "'");
    EXPECT_EQ(usage.message().size(), 8u + WITH_NUL.size());
}

TEST(Printable, EscapesControlBytesAndInvalidUtf8) {
    EXPECT_EQ(printable(WITH_NUL), "a\\x00b.png: does not exist");
    EXPECT_EQ(printable("tab\there\nnew"), "tab\\x09here\\x0anew");
    EXPECT_EQ(printable("caf\xc3\xa9 \xff"), "caf\xc3\xa9 \\xff"); // é kept, a lone 0xff escaped
    EXPECT_EQ(printable("\x7f"), "\\x7f");
    EXPECT_EQ(printable("plain text"), "plain text");
}

TEST(Printable, CutsLongTextWithAnEllipsis) {
    EXPECT_EQ(printable(std::string(10, 'x'), 4), "xxxx...");
    EXPECT_EQ(printable(std::string(4, 'x'), 4), "xxxx") << "text that fits is not marked as cut";
    EXPECT_EQ(printable(std::string(1000000, '1')).size(), 403u);
}

} // namespace
} // namespace stsv
