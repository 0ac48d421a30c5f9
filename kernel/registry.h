#ifndef SPLAM_KERNEL_REGISTRY_H_
#define SPLAM_KERNEL_REGISTRY_H_

#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace splam::kernel {

// name -> Info (a struct with `name` and `description` strings), for the variants a user adds
// beside the built-in ones (SLAM methods, explorers). Registration cannot fail by where it is
// placed:
// - the built-in entries are added the first time the registry is used, by `builtins`, outside
//   any static initialisation guard, and `builtins` may itself register (a new entry written
//   beside the built-in ones) or look entries up: a nested use sees the entries added so far;
// - a registry reached through a function-local static (Global() of the users) is constructed
//   on first use, whatever translation unit's static initialiser gets there first;
// - every member is thread-safe, and an entry's address stays valid (entries are never removed:
//   adding a known name replaces that entry in place).
template <class Info>
class Registry {
 public:
  explicit Registry(std::function<void(Registry*)> builtins) : builtins_(std::move(builtins)) {}
  Registry(const Registry&) = delete;
  Registry& operator=(const Registry&) = delete;

  // Adds an entry, or replaces the one of the same name.
  void Add(Info info) {
    const std::lock_guard lock(mutex_);
    AddBuiltins();
    for (Info& known : entries_) {
      if (known.name == info.name) {
        known = std::move(info);
        return;
      }
    }
    entries_.push_back(std::move(info));
  }
  // nullptr for an unknown name.
  const Info* Find(const std::string& name) const {
    const std::lock_guard lock(mutex_);
    AddBuiltins();
    for (const Info& known : entries_)
      if (known.name == name) return &known;
    return nullptr;
  }
  // In registration order, the built-in entries first.
  std::vector<std::string> Names() const {
    const std::lock_guard lock(mutex_);
    AddBuiltins();
    std::vector<std::string> names;
    for (const Info& known : entries_) names.push_back(known.name);
    return names;
  }
  // The names joined by ", " (for messages and help).
  std::string NameList() const {
    std::string list;
    for (const std::string& name : Names()) list += (list.empty() ? "" : ", ") + name;
    return list;
  }
  // "name: description" a line each, for help texts.
  std::string Describe() const {
    const std::lock_guard lock(mutex_);
    AddBuiltins();
    std::string text;
    for (const Info& known : entries_)
      text += (text.empty() ? "" : "\n") + known.name + ": " + known.description;
    return text;
  }

 private:
  // Called with mutex_ held (recursive: `builtins_` may come back in on this thread).
  void AddBuiltins() const {
    if (builtins_added_) return;
    builtins_added_ = true;  // first, so that a nested use does not start them again
    if (builtins_) builtins_(const_cast<Registry*>(this));
  }

  std::function<void(Registry*)> builtins_;
  mutable bool builtins_added_ = false;
  mutable std::recursive_mutex mutex_;
  std::deque<Info> entries_;  // a deque: adding keeps the addresses Find gave
};

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_REGISTRY_H_
