// Context Free's front end (ReadDesign.h).
#include "frontend/cfdg/ReadDesign.h"

#include <cstdlib>

#include "frontend/cfdg/Parser.h"

namespace lcjit::frontend::cfdg {

llvm::Expected<DesignUnit> readDesign(std::string_view text, const std::string& file,
                                      const std::vector<std::string>& defines) {
  auto design = parseDesign(text, file, defines);
  if (!design) return design.takeError();
  auto translation = translateDesign(*design);
  if (!translation) return translation.takeError();
  DesignUnit unit{std::move(*translation), design->imports, {}};
  for (const Definition& d : design->definitions) {
    if (d.config || d.isFunction || !d.value || !(d.type.empty() || d.type == "number")) continue;
    // A number as written, or one with a sign before it.
    const Expr* e = d.value.get();
    double sign = 1;
    if (e->kind == Expr::Unary && (e->text == "-" || e->text == "+") && e->args.size() == 1) {
      sign = e->text == "-" ? -1 : 1;
      e = e->args[0].get();
    }
    if (e->kind != Expr::Number) continue;
    unit.variables.push_back({d.name, sign * numberValue(e->text), d.commandLine ? 0 : d.at.line});
  }
  return unit;
}

}  // namespace lcjit::frontend::cfdg
