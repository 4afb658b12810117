// Whether a tracker's reading holds a pair of the bodies: a table of named rules applied in
// order (docs/behaviour.md), the first that rejects the reading naming it (Live::rejected_by,
// the report's detail when the solver answers instead). Not API.
#pragma once

#include <array>

#include "algorithms/body_pair/internal/Live_set.h"

namespace extremal::internal {

// A reading as the rules see it: the slot (its result and its provenance),
// its primitives, and the pair's context (poses, kind, tolerances).
struct Reading {
  const Live& slot;
  const Primitive& a;
  const Primitive& b;
  Pair_context& context;
};

struct Rule_entry {
  Reading_rule rule;
  // Whether the rule rejects the reading; rules after the first that does are not applied.
  bool (*rejects)(const Reading&);
};
// In the order applied. The first two run before the reading's passage through contact is
// recorded (they decide it); the last runs after all others, so that a reading it alone
// rejects is known (holds_unreached, Live_set.h).
extern const std::array<Rule_entry, 9> k_reading_rules;

// Judges slot L's reading, just stepped (`first`: its first step): sets L.valid, L.rejected_by
// and L.provenance.
void judge(Live& L, bool first, Pair_context& context);

// Whether rule r alone rejects slot L's reading as it stands (for tests).
bool rule_rejects(Reading_rule r, const Live& L, Pair_context& context);

}  // namespace extremal::internal
