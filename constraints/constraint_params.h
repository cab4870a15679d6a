// The fields of a constraint type's params struct, as a table: each type's
// params declare theirs (Fields(): name as declared, member, documentation)
// and a one-line summary, and mochi's params class, the API fuzzer and the
// docs table are made from them (constraint_types.h).
#pragma once

#include <string_view>
#include <variant>

#include <superdex/core/handle.h>
#include <superdex/core/types.h>

namespace superdex::internal {

template <class Params>
struct ParamsField {
  using Member = std::variant<ActorHandle Params::*, int Params::*, real Params::*, bool Params::*,
                              Real3 Params::*, Quat Params::*>;
  std::string_view name;  ///< as declared (camelCase)
  Member member;
  std::string_view doc;   ///< what it is, its units and its default
};

}  // namespace superdex::internal
