// The flags that set members of the render request: one table that `render`, `bench-render` and
// `import` read. A flag's value is checked here for syntax only (a UsageError naming the flag, exit
// 2); it is then written into the request before validation, so the validator checks it like the
// member it replaces (an InputError at that member's pointer, exit 1). Flags win over the file.
#pragma once

#include "cli/args.hpp"
#include "render/import/import.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace rr::cli {

// The request-setting flags, for parse_args; `own` are the subcommand's other flags.
std::vector<std::string_view> with_request_flags(std::initializer_list<std::string_view> own);

// One "--flag VALUE  what it sets" line per table row, the value names taken from the build's tables.
std::string request_flags_help();

struct RequestPatch {
  struct Entry {
    std::string pointer;  // the member the flag sets, e.g. /camera/fov_y
    nlohmann::json value;
  };
  std::vector<Entry> entries;
  FlagByPointer flag_by_pointer;  // "/camera/fov_y" -> "--fovy", for error lines

  const nlohmann::json* find(const std::string& pointer) const;
};

// The flags present in `args` as a patch; throws UsageError naming the flag whose value is malformed.
RequestPatch request_patch(const ParsedArgs& args);

// The request with the patch written into it. A member on the way that is neither absent nor an
// object is left as it is, for the validator to report against the file.
nlohmann::json apply_request_patch(nlohmann::json request, const RequestPatch& patch);

// Importer options from --scale and --furniture, and the image size the patch sets (the importer
// fits the default camera's field of view to the aspect).
ImportOptions import_options(const ParsedArgs& args, const RequestPatch& patch);

// FILE imported (format given, or recognised when nullopt) as request JSON text; the importer's
// warnings go to stderr as JSON lines.
std::string imported_request_text(const std::string& file, std::optional<ImportFormat> format,
                                  const ImportOptions& options);

}  // namespace rr::cli
