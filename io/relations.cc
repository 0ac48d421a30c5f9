#include "io/relations.h"

#include "io/text.h"
#include "io/trajectory.h"

namespace splam::io {

Result<std::vector<evaluation::Relation>> ParseRelations(const std::string& text,
                                                         const std::string& name) {
  using R = Result<std::vector<evaluation::Relation>>;
  std::vector<evaluation::Relation> relations;
  std::vector<double> v;
  const kernel::Status error =
      ForEachDataLine(text, [&](int line, const std::vector<std::string_view>& tokens) {
        if (tokens.size() != 8) {
          return FileError(name, line,
                           "expected 8 values 't1 t2 x y z roll pitch yaw', found " +
                               std::to_string(tokens.size()));
        }
        if (kernel::Status bad = ParseFiniteNumbers(tokens, &v); !bad.ok())
          return FileError(name, line, bad.message());
        relations.push_back({v[0], v[1], kernel::Pose2(v[2], v[3], v[7])});
        return kernel::Status::Ok();
      });
  if (!error.ok()) return R::Fail(error);
  if (relations.empty()) return R::Fail(FileError(name, 0, "no relations"));
  return R::Ok(std::move(relations));
}

Result<std::vector<evaluation::Relation>> ReadRelations(const std::string& path) {
  std::string text;
  if (kernel::Status error = ReadTextFile(path, &text); !error.ok()) {
    return Result<std::vector<evaluation::Relation>>::Fail(error);
  }
  return ParseRelations(text, path);
}

}  // namespace splam::io
