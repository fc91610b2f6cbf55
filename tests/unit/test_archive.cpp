// The bounded zip reader (render/import/archive.hpp) on archives built in memory: entry lookup by
// exact and base name, and each limit and refusal with small limits (entry count, per-entry and total
// sizes, compression ratio, headers that lie about sizes, unsafe names, corrupt and truncated data),
// each an InputError of the documented kind at "/entry/<name>".
#include "render/import/archive.hpp"
#include "support/zip_builder.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <random>

namespace {

using rr::Archive;
using rr::ArchiveLimits;
using rr::InputError;
using rr::testing::make_zip;
using Kind = InputError::Kind;

// Bytes that deflate cannot shrink: a ratio of ~1.
std::string noise(size_t size, unsigned seed) {
  std::mt19937 random(seed);
  std::string out(size, '\0');
  for (char& c : out) c = char(random() & 0xff);
  return out;
}

// Runs `f` and returns the InputError it throws; fails the test when it throws none.
InputError error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError";
  return InputError(Kind::malformed, "<none>", "no error");
}

TEST(Archive, ReadsEntriesAndResolvesNamesExactlyThenByBaseName) {
  const std::string zip = make_zip({{"Home.xml", "<home/>"},
                                    {"furniture/", ""},
                                    {"12/chair.obj", "v 0 0 0\n"},
                                    {"furniture/chair.obj", "v 1 1 1\n"},
                                    {"chair.mtl", "newmtl a\n", false}});
  Archive archive(zip);
  EXPECT_EQ(archive.names(),
            (std::vector<std::string>{"Home.xml", "12/chair.obj", "furniture/chair.obj", "chair.mtl"}));
  EXPECT_EQ(archive.resolve("furniture/chair.obj"), "furniture/chair.obj");
  // Not an entry: the shallowest entry of that base name, the first in the archive among equals.
  EXPECT_EQ(archive.resolve("com/eteks/sweethome3d/io/resources/chair.obj"), "12/chair.obj");
  EXPECT_EQ(archive.resolve("x/chair.mtl"), "chair.mtl");
  EXPECT_EQ(archive.resolve("hair.obj"), std::nullopt);  // a base name matches whole names only
  EXPECT_EQ(archive.resolve("sofa.obj"), std::nullopt);
  EXPECT_EQ(archive.read("furniture/chair.obj"), "v 1 1 1\n");
  EXPECT_EQ(archive.read("chair.mtl"), "newmtl a\n");
}

TEST(Archive, MoreEntriesThanTheCapAreRefusedNamingTheFirstOneOver) {
  ArchiveLimits limits;
  limits.max_entries = 3;
  const std::string zip = make_zip({{"a", "1"}, {"b", "2"}, {"c", "3"}, {"d", "4"}});
  InputError e = error_of([&] { Archive archive(zip, limits); });
  EXPECT_EQ(e.kind(), Kind::too_large);
  EXPECT_EQ(e.pointer(), "/entry/d");
  EXPECT_NE(std::string(e.what()).find("4 entries"), std::string::npos) << e.what();
  const std::string three = make_zip({{"a", "1"}, {"b", "2"}, {"c", "3"}});
  EXPECT_NO_THROW(Archive archive(three, limits));
}

TEST(Archive, UnsafeNamesAreRefused) {
  for (const std::string name : {"../x", "a/../../x", "a/..", "/etc/x", "C:/x", "a\\..\\x"}) {
    const std::string zip = make_zip({{"ok.txt", "1"}, {name, "2"}});
    InputError e = error_of([&] { Archive archive(zip); });
    EXPECT_EQ(e.kind(), Kind::invalid) << name;
    EXPECT_EQ(e.pointer(), rr::entry_pointer(name)) << name;
  }
  EXPECT_EQ(rr::entry_pointer("furniture/chair.obj"), "/entry/furniture~1chair.obj");
  const std::string dots = make_zip({{"a..b/..c", "1"}, {"./x", "2"}});
  EXPECT_NO_THROW(Archive archive(dots));  // dots that are no step up
  // libzip will not write one name twice: write two, then make the second name the first.
  std::string zip = make_zip({{"dup-one", "1"}, {"dup-two", "2"}});
  for (size_t at = zip.find("dup-two"); at != std::string::npos; at = zip.find("dup-two"))
    zip.replace(at, 7, "dup-one");
  InputError twice = error_of([&] { Archive archive(zip); });
  EXPECT_EQ(twice.kind(), Kind::invalid);
}

TEST(Archive, EntryAndTotalSizesAreCappedBeforeInflating) {
  ArchiveLimits limits;
  limits.max_entry_bytes = 1000;
  limits.max_total_bytes = 2500;
  const std::string zip = make_zip({{"small", noise(900, 1)}, {"big", noise(1001, 2)}});
  Archive archive(zip, limits);
  EXPECT_EQ(archive.read("small").size(), 900u);
  InputError big = error_of([&] { archive.read("big"); });
  EXPECT_EQ(big.kind(), Kind::too_large);
  EXPECT_EQ(big.pointer(), "/entry/big");
  // Declared sizes over the total refuse the archive when it opens.
  const std::string over = make_zip({{"a", noise(900, 3)}, {"b", noise(900, 4)}, {"c", noise(900, 5)}});
  InputError total = error_of([&] { Archive refused(over, limits); });
  EXPECT_EQ(total.kind(), Kind::too_large);
  EXPECT_EQ(total.pointer(), "/entry/c");
}

TEST(Archive, TotalIsCountedOnTheBytesReadWhenHeadersUnderstate) {
  ArchiveLimits limits;
  limits.max_total_bytes = 2500;
  std::string zip = make_zip({{"a", noise(900, 6), false}, {"b", noise(900, 7), false}, {"c", noise(900, 8), false}});
  zip = rr::testing::with_declared_size(zip, "c", 10);  // the directory now claims 1810 bytes in all
  Archive archive(zip, limits);
  archive.read("a");
  archive.read("b");
  InputError e = error_of([&] { archive.read("c"); });
  EXPECT_EQ(e.pointer(), "/entry/c");
}

TEST(Archive, ZipBombIsRefusedByRatioBeforeAndWhileInflating) {
  ArchiveLimits limits;  // the defaults: 100:1 past 1 MiB
  const std::string zeros(8u << 20, '\0');
  const std::string zip = make_zip({{"bomb", zeros}});
  ASSERT_LT(zip.size(), zeros.size() / 100);
  Archive honest(zip, limits);
  InputError before = error_of([&] { honest.read("bomb"); });
  EXPECT_EQ(before.kind(), Kind::too_large);
  EXPECT_EQ(before.pointer(), "/entry/bomb");
  EXPECT_NE(std::string(before.what()).find("zip bomb"), std::string::npos) << before.what();
  // A header that claims 1000 bytes gets past the first check; the inflating does not.
  const std::string lie = rr::testing::with_declared_size(zip, "bomb", 1000);
  Archive lying(lie, limits);
  InputError during = error_of([&] { lying.read("bomb"); });
  EXPECT_EQ(during.pointer(), "/entry/bomb");
  // Under the floor, a high ratio is no bomb.
  const std::string small = make_zip({{"zeros", std::string(1000, '\0')}});
  EXPECT_EQ(Archive(small).read("zeros").size(), 1000u);
}

TEST(Archive, CorruptAndTruncatedArchivesNameTheEntry) {
  const std::string text = noise(20000, 9);
  std::string zip = make_zip({{"first.txt", "hello"}, {"models/chair.obj", text}});
  // Damage the deflated data of the second entry (past its local header), not the directory.
  std::string corrupt = zip;
  const size_t data = corrupt.find("models/chair.obj") + 16 + 5000;
  for (size_t k = 0; k < 64; ++k) corrupt[data + k] = char(corrupt[data + k] ^ 0x5a);
  Archive damaged(corrupt);
  EXPECT_EQ(damaged.read("first.txt"), "hello");
  InputError bad = error_of([&] { damaged.read("models/chair.obj"); });
  EXPECT_EQ(bad.kind(), Kind::malformed);
  EXPECT_EQ(bad.pointer(), "/entry/models~1chair.obj");

  InputError cut = error_of([&] { Archive archive(std::string_view(zip).substr(0, zip.size() / 2)); });
  EXPECT_EQ(cut.kind(), Kind::malformed);
  EXPECT_EQ(cut.pointer(), "/entry/models~1chair.obj");
  EXPECT_NE(std::string(cut.what()).find("truncated"), std::string::npos) << cut.what();

  InputError not_zip = error_of([&] { Archive archive(std::string_view("<home/>")); });
  EXPECT_EQ(not_zip.kind(), Kind::malformed);
  EXPECT_EQ(not_zip.pointer(), "");
}

TEST(Archive, ErrorsInsideAnEntryArePrefixedWithIt) {
  InputError e = rr::error_in_entry(InputError(Kind::invalid, "/line/3", "line 3: bad"), "a/b.obj");
  EXPECT_EQ(e.kind(), Kind::invalid);
  EXPECT_EQ(e.pointer(), "/entry/a~1b.obj/line/3");
  EXPECT_EQ(std::string(e.what()), "entry 'a/b.obj': line 3: bad");
}

}  // namespace
