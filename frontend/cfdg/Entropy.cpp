// Context Free's seed bytes (Entropy.h). The constants are data: Context Free 3.4's fixed byte
// strings for each operator, function and adjustment word, which decide every seed.
#include "frontend/cfdg/Entropy.h"

#include <map>

#include "runtime/cfdg/Expander.h"  // stepSeed

namespace lcjit::frontend::cfdg {
namespace {

std::string bytesOf(std::string_view hex) {
  std::string out;
  for (size_t i = 0; i + 1 < hex.size(); i += 2)
    out.push_back(char(std::stoi(std::string(hex.substr(i, 2)), nullptr, 16)));
  return out;
}

// Context Free's built-in functions, by name, and their bytes ("rand2": `+/-`).
const std::map<std::string_view, std::string_view>& functionHex() {
  static const std::map<std::string_view, std::string_view> kHex = {
      {"cos", "A1E79C1AAF7D"}, {"sin", "AF58FE2CD453"}, {"tan", "95FF59110302"}, {"cot", "77F5B6358CF0"},
      {"acos", "3ACD793EADB4"}, {"asin", "1D750BBC5F52"}, {"atan", "0BC889ABF8B7"}, {"acot", "697CC71AF67B"},
      {"cosh", "484343356281"}, {"sinh", "5162FB76ED9C"}, {"tanh", "BB9154A96384"}, {"acosh", "4F284820B75C"},
      {"asinh", "6C9B32AA4CD0"}, {"atanh", "58ECBB25F8B6"}, {"log", "8EB862A1750F"}, {"log10", "4A6CA3028B80"},
      {"sqrt", "867CFC20CB97"}, {"exp", "88A865F0C106"}, {"abs", "418918D1AD82"}, {"floor", "B728D7D7A3CC"},
      {"ceiling", "F796027C27E4"}, {"infinity", "2C2850CCDE44"}, {"factorial", "19D783294799"},
      {"sg", "B70528BACD2E"}, {"isNatural", "49D6F85B4559"}, {"bitnot", "79191A9F4DA0"},
      {"bitor", "F277AB5C3343"}, {"bitand", "C3569E75E044"}, {"bitxor", "BBFA2BD29155"},
      {"bitleft", "9147E5E50DAA"}, {"bitright", "F1AB17"}, {"atan2", "991BC9E03FA4"},
      {"divides", "788EC82C1C96"}, {"div", "64EC5B4BEE2B"}, {"dot", "60AAB7E1B906"}, {"cross", "393840E593F8"},
      {"hsb2rgb", "C3D45704AF9F"}, {"rgb2hsb", "D02A557A5397"}, {"vec", "E17595C980CF"}, {"mod", "0FE3FE5FBFBF"},
      {"min", "A242A349B119"}, {"max", "D3555C0DD851"}, {"ftime", "4FBEA1068006"}, {"frame", "90706ABBBAB0"},
      {"rand_static", "C8F7E53E05A3"}, {"rand", "DA185BE2DB79"}, {"rand2", "DC8D09158AC4"},
      {"rand::exponential", "32DF4AFD"}, {"rand::gamma", "C9D5574FE677"}, {"rand::weibull", "E7CFA201CD02"},
      {"rand::extremeV", "E8CF860BFD8E"}, {"rand::normal", "CFACD41209CC"}, {"rand::lognormal", "3665085C49AA"},
      {"rand::chisquared", "6D4B49A883AD"}, {"rand::cauchy", "226C9E777989"}, {"rand::fisherF", "9B761B51CDAE"},
      {"rand::studentT", "F94144F263A7"}, {"randint", "48144E27352E"}, {"randint::bernoulli", "BED15504D454"},
      {"randint::binomial", "6A699A94366C"}, {"randint::negbinomial", "ED31469CA6AD"},
      {"randint::poisson", "0989F377AE67"}, {"randint::discrete", "17698D61FF2A"},
      {"randint::geometric", "D5102EA503B4"}};
  return kHex;
}

}  // namespace

std::string hotbits(std::string_view what) {
  static const std::map<std::string_view, std::string_view> kHex = {
      // adjustment words
      {"x", "95E7485ECC06"}, {"y", "842BF3BB9359"}, {"z", "C83A12323671"}, {"xyz", "6C31CABF8D89"},
      {"trans", "889054C5D320"}, {"s", "64EC5B4BEE2B"}, {"sizexyz", "B031D51E7A5A"},
      {"zsize", "64EC5B4BEE2B"}, {"r", "84B0922659E2"}, {"skew", "FF2D8401A00A"}, {"f", "435A17EA1205"},
      {"blend", "BE9F5F7F4A7E"}, {"h", "02DE2B2C25A1"}, {"sat", "184FCF043FE5"}, {"b", "1F3FEBA2A27E"},
      {"a", "B4FF9E45EE7E"}, {"h|", "AFE5583320F8"}, {"sat|", "9880ED442FF2"}, {"b|", "68D6CB8A9620"},
      {"a|", "244CCC4109C7"}, {"|h", "DB3FA1DAE745"}, {"|sat", "DA7513D330EA"}, {"|b", "8F012B75C325"},
      {"|a", "E7CD5EE388F4"}, {"time", "20C6E802ED27"}, {"timescale", "788EC82C1C96"},
      // operators
      {"*", "2E32D92C41FE"}, {"/", "6B1523419EEB"}, {"+", "D7B1B03933C8"}, {"-", "5DE7F094C413"},
      {"^", "023C6836C5A0"}, {"N", "55895146DB84"}, {"P", "8EAC294B0EDC"}, {"!", "193A3E5314EA"},
      {"<", "BEDBC4A64EAD"}, {">", "C7D95732D687"}, {"<=", "E3567E445780"}, {">=", "B12D2ACC2C40"},
      {"==", "7848C295A9E2"}, {"<>", "36CC013B2FAD"}, {"&&", "289BFB7FDB9C"}, {"||", "2E401B44157C"},
      {"^^", "A72B92FAFCF9"}, {"--", "602F10AD10FF"}, {"cons", "C560A5C5C874"}, {"paren", "E8E9F67E1AF1"},
      {"select", "B5A24A74A9DF"}};
  auto it = kHex.find(what);
  if (it != kHex.end()) return bytesOf(it->second);
  auto f = functionHex().find(what);
  return f == functionHex().end() ? std::string() : bytesOf(f->second);
}

bool builtinFunction(std::string_view name) { return name != "rand2" && functionHex().count(name) != 0; }

uint64_t mixBytes(uint64_t s, std::string_view bytes, int& i) {
  for (char ch : bytes) {
    auto c = static_cast<unsigned char>(ch);
    if (c == 0)
      break;
    s ^= uint64_t(c) << (8 * i);
    s = runtime::cfdg::stepSeed(s);
    i = (i + 1) & 7;
  }
  return s;
}

}  // namespace lcjit::frontend::cfdg
