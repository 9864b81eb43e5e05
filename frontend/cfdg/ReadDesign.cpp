// Context Free's front end (ReadDesign.h).
#include "frontend/cfdg/ReadDesign.h"

#include "frontend/cfdg/Parser.h"

namespace lcjit::frontend::cfdg {

llvm::Expected<DesignUnit> readDesign(std::string_view text, const std::string& file,
                                      const std::vector<std::string>& defines) {
  auto design = parseDesign(text, file, defines);
  if (!design) return design.takeError();
  auto translation = translateDesign(*design);
  if (!translation) return translation.takeError();
  return DesignUnit{std::move(*translation), design->imports};
}

}  // namespace lcjit::frontend::cfdg
