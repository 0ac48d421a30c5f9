#include "kernel/registry.h"

#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

namespace splam::kernel {
namespace {

struct Entry {
  std::string name, description;
  int value = 0;
};
using EntryRegistry = Registry<Entry>;

// A registry reached as the programs reach theirs: a function-local static whose built-in
// entries include one registered through that same accessor (a line written beside them), and a
// lookup of an entry added just before.
EntryRegistry& Global();
void Builtins(EntryRegistry* registry) {
  registry->Add({"first", "built in", 1});
  Global().Add({"beside", "registered through Global() while it adds its built-ins", 2});
  EXPECT_NE(Global().Find("first"), nullptr);
  registry->Add({"last", "built in", 3});
}
EntryRegistry& Global() {
  static EntryRegistry registry(Builtins);
  return registry;
}

// A namespace-scope registration in this translation unit: it runs during static
// initialisation, before main, and the built-in entries still come first.
const bool kRegisteredEarly = [] {
  Global().Add({"early", "registered by a static initialiser", 4});
  return true;
}();

TEST(Registry, BuiltinsComeFirstAndMayRegisterThroughTheRegistryItself) {
  ASSERT_TRUE(kRegisteredEarly);
  const std::vector<std::string> names = Global().Names();
  ASSERT_GE(names.size(), 4u);
  EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + 4),
            (std::vector<std::string>{"first", "beside", "last", "early"}));
  EXPECT_EQ(Global().Find("beside")->value, 2);
  EXPECT_EQ(Global().Find("nothing"), nullptr);
  EXPECT_EQ(Global().NameList().substr(0, 26), "first, beside, last, early");
}

TEST(Registry, AddingAKnownNameReplacesItInPlace) {
  EntryRegistry registry({});
  registry.Add({"a", "one", 1});
  const Entry* a = registry.Find("a");
  registry.Add({"b", "two", 2});
  for (int i = 0; i < 1000; ++i) registry.Add({"c" + std::to_string(i), "more", i});
  registry.Add({"a", "again", 5});
  EXPECT_EQ(registry.Find("a"), a);  // the address stays valid
  EXPECT_EQ(a->value, 5);
  EXPECT_EQ(registry.Names().size(), 1002u);
  EXPECT_EQ(registry.Describe().substr(0, 20), "a: again\nb: two\nc0: ");
}

// Threads register and look up at once (run under ThreadSanitizer by scripts/tsan.sh): every
// entry lands once, and the built-ins are added once.
TEST(Registry, ThreadsRegisterAndLookUpAtOnce) {
  int builtin_calls = 0;
  EntryRegistry registry([&](EntryRegistry* r) {
    ++builtin_calls;
    r->Add({"built-in", "", 0});
  });
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&registry, t] {
      for (int i = 0; i < 200; ++i) {
        registry.Add({std::to_string(t) + "-" + std::to_string(i), "", i});
        EXPECT_NE(registry.Find("built-in"), nullptr);
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(builtin_calls, 1);
  EXPECT_EQ(registry.Names().size(), 801u);
}

}  // namespace
}  // namespace splam::kernel
