// The encoders of harness/encode.hpp: each output keeps what it must and cannot be ended or
// steered by the text it carries.
#include "harness/encode.hpp"

#include <gtest/gtest.h>

#include "harness/markup.hpp"
#include "test_util.hpp"

namespace {

namespace encode = harness::encode;

TEST(Encode, HtmlAndXmlEscapeAndReplaceWhatXmlForbids) {
    EXPECT_EQ(encode::html_text("a<b>&\"'"), "a&lt;b&gt;&amp;&quot;&#39;");
    // Controls XML 1.0 forbids, an escape sequence's ESC included, and bytes that are not UTF-8
    // become U+FFFD; tab and newline stay in text and become references in attributes.
    EXPECT_EQ(encode::xml_text("x\x1b[31m\x01y"), "x\xEF\xBF\xBD[31m\xEF\xBF\xBDy");
    EXPECT_EQ(encode::xml_text("\xff\xc3"), "\xEF\xBF\xBD\xEF\xBF\xBD");
    EXPECT_EQ(encode::xml_text("\xEF\xBF\xBE"), "\xEF\xBF\xBD");  // U+FFFE
    EXPECT_EQ(encode::xml_text("a\tb\nc"), "a\tb\nc");
    EXPECT_EQ(encode::xml_attribute("a\tb\nc\r"), "a&#9;b&#10;c&#13;");
    // Good UTF-8 passes, an overlong form and a surrogate do not.
    EXPECT_EQ(encode::html_text("\xE2\x89\xA4\xF0\x9F\x98\x80"), "\xE2\x89\xA4\xF0\x9F\x98\x80");
    EXPECT_EQ(encode::html_text("\xC0\xAF"), "\xEF\xBF\xBD\xEF\xBF\xBD");
    EXPECT_EQ(encode::html_text("\xED\xA0\x80"), "\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD");
    // The markup helper every page uses is the same encoder.
    EXPECT_EQ(harness::markup::escape("\x1b<"), "\xEF\xBF\xBD&lt;");
}

// One shell word: safe words as they are, anything else single-quoted with its quotes escaped,
// so that `sh -c "printf %s WORD"` prints the text back.
TEST(Encode, ShellWordReadsBackAsTheText) {
    EXPECT_EQ(harness::encode::shell_word("conformance/scenes/a_b-1.json"),
              "conformance/scenes/a_b-1.json");
    EXPECT_EQ(harness::encode::shell_word("tie_rule=right-top"), "tie_rule=right-top");
    EXPECT_EQ(harness::encode::shell_word(""), "''");
    EXPECT_EQ(harness::encode::shell_word("a b"), "'a b'");
    for (const std::string text : {"it's", "$(rm -rf /)", "a\nb", "`x` ; y", "*?[]~#&|<>\"!"}) {
        const std::string out =
            testutil::command_output("printf %s " + harness::encode::shell_word(text));
        EXPECT_EQ(out, text) << harness::encode::shell_word(text);
    }
}

TEST(Encode, JsonInScriptCannotCloseTheScript) {
    const std::string s = encode::json_in_script("</script><!-- & \"q\" \\ \n\x01\xE2\x80\xA8\xff");
    EXPECT_EQ(s,
              "\"\\u003c/script\\u003e\\u003c!-- \\u0026 \\\"q\\\" \\\\ \\n\\u0001\\u2028"
              "\\ufffd\"");
    EXPECT_EQ(s.find('<'), std::string::npos);
    EXPECT_EQ(encode::json_in_script(""), "\"\"");
}

// The one JSON string encoder: the scene reader's normalized copy and the pages' scripts both
// use it; a page's embedded document (teach) goes through script_safe_json alone.
TEST(Encode, JsonStringAndScriptSafeDocument) {
    EXPECT_EQ(encode::json_string("a\"b\\c\n\x1f\x7f\xE2\x80\xA8"),
              "\"a\\\"b\\\\c\\n\\u001f\\u007f\xE2\x80\xA8\"");
    EXPECT_EQ(encode::script_safe_json("{\"k\":\"</script>\xE2\x80\xA9&\"}"),
              "{\"k\":\"\\u003c/script\\u003e\\u2029\\u0026\"}");
}

TEST(Encode, CsvFieldsQuoteAsRfc4180Says) {
    EXPECT_EQ(encode::csv_field("smoke.triangles"), "smoke.triangles");
    EXPECT_EQ(encode::csv_field("a,b"), "\"a,b\"");
    EXPECT_EQ(encode::csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
    EXPECT_EQ(encode::csv_field("a\nPass,x"), "\"a\nPass,x\"");
    EXPECT_EQ(encode::csv_field("a\rb"), "\"a\rb\"");
}

TEST(Encode, TerminalShowsControlsAsEscapes) {
    EXPECT_EQ(encode::terminal("x\ny\tz\r"), "x\\ny\\tz\\r");
    EXPECT_EQ(encode::terminal("\x1b[2J\x07\x7f"), "\\x1B[2J\\x07\\x7F");
    EXPECT_EQ(encode::terminal("bad \xff byte"), "bad \\xFF byte");
    EXPECT_EQ(encode::terminal("\xC2\x9B"), "\\u{009B}");      // C1 CSI
    EXPECT_EQ(encode::terminal("\xE2\x80\xAE"), "\\u{202E}");  // right-to-left override
    EXPECT_EQ(encode::terminal("caf\xC3\xA9 \xE2\x89\xA4 1,2 a\\b"),
              "caf\xC3\xA9 \xE2\x89\xA4 1,2 a\\b");
    // Encoding twice changes nothing: what comes out holds nothing to encode.
    const std::string once = encode::terminal("\x1b\n\xff");
    EXPECT_EQ(encode::terminal(once), once);
}

}  // namespace
