// Every shipped scene rendered by the reference hashes to the value recorded in
// conformance/expectations/ref-hashes.txt: any change of the reference's output shows here,
// without a GL driver. Regenerate the file with the command in its header after a deliberate
// change.
#include <gtest/gtest.h>

#include <map>

#include "harness/backend.hpp"
#include "harness/image_hash.hpp"
#include "test_util.hpp"

namespace {

TEST(GoldenHashes, ReferenceImagesAreUnchanged) {
    const std::filesystem::path root = std::filesystem::path(REFRASTER_SOURCE_DIR) / "conformance";
    std::map<std::string, std::string> golden;
    std::stringstream file(testutil::read_text(root / "expectations/ref-hashes.txt"));
    for (std::string line; std::getline(file, line);) {
        if (line.empty() || line[0] == '#') continue;
        const auto sp = line.find(' ');
        golden[line.substr(0, sp)] = line.substr(sp + 1);
    }
    harness::BackendOptions o;
    o.profile.gl.viewport_fma = refraster::FmaMode::On;
    auto ref = harness::make_backend(o);
    std::size_t checked = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(root / "scenes")) {
        if (e.path().extension() != ".json") continue;
        auto name = std::filesystem::relative(e.path(), root / "scenes")
                        .replace_extension("")
                        .generic_string();
        std::replace(name.begin(), name.end(), '/', '.');
        SCOPED_TRACE(name);
        ASSERT_TRUE(golden.count(name)) << "no golden hash: regenerate ref-hashes.txt";
        const auto r = ref->render(harness::load_scene(e.path()));
        const std::string got = r.status == harness::RenderStatus::Ok
                                    ? harness::render_hash(r.image, r.samples)
                                    : std::string(harness::to_string(r.status));
        EXPECT_EQ(got, golden.at(name));
        ++checked;
    }
    EXPECT_EQ(checked, golden.size());
    EXPECT_GE(checked, 180u);
}

}  // namespace
