// The names of Dinero IV's fetch policies, on our command lines and on its.
#include <array>

#include "nodetrace/cachesim/dinero/engine.hpp"

namespace nodetrace::cachesim {

namespace {

struct Names {
  FetchPolicy policy;
  std::string_view name;
  char letter;
};
constexpr std::array<Names, 6> kNames{{{FetchPolicy::Demand, "demand", 'd'},
                                       {FetchPolicy::Always, "always", 'a'},
                                       {FetchPolicy::Miss, "miss", 'm'},
                                       {FetchPolicy::Tagged, "tagged", 't'},
                                       {FetchPolicy::LoadForward, "load-forward", 'l'},
                                       {FetchPolicy::SubBlock, "subblock", 's'}}};

}  // namespace

std::string_view fetch_policy_name(FetchPolicy policy) {
  for (const Names& n : kNames) {
    if (n.policy == policy) return n.name;
  }
  return "demand";
}

std::optional<FetchPolicy> parse_fetch_policy_name(std::string_view name) {
  for (const Names& n : kNames) {
    if (n.name == name) return n.policy;
  }
  return std::nullopt;
}

char dinero_fetch_letter(FetchPolicy policy) {
  for (const Names& n : kNames) {
    if (n.policy == policy) return n.letter;
  }
  return 'd';
}

}  // namespace nodetrace::cachesim
