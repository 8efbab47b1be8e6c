// Names as hints for the automatic rig (rig/auto_rig.h), Character Animator's way: the words of
// a part's or a group's id or label (case-insensitive) say what it is — head, body, a limb, a
// hand, a mouth, an eye — and what the rig makes of them besides its parts' tree: swap sets
// (mouths, eyes, any group of alternatives one of which shows), a blink, and chains that swing.
#pragma once

#include "character/character.h"
#include "rig/auto_rig.h"

#include <initializer_list>
#include <set>
#include <string>
#include <vector>

namespace mar {

/// What a word says about a part.
enum class Hint { None, Head, Body, Limb, Hand, Mouth, Eye };
Hint hint_of(const std::vector<std::string>& words);
bool has_word(const std::vector<std::string>& words, std::initializer_list<const char*> any);
/// An id the loader made up ("path-L12") or an editor's default ("path1234", "g12"): no name.
bool made_up(const std::string& id);
/// A handle name from a part's id: lower case, words joined by '-'.
std::string handle_name(const std::string& id);
/// `base`, or `base-2`, `base-3`, ... the first not in `used`; added to it.
std::string unique_name(std::set<std::string>& used, const std::string& base);

/// Swap sets and triggers from names and groups: a `mouth` of visemes, `eyes` open and shut
/// with a `blink`, a blink layer, any other group of alternatives one of which shows. Returns
/// the shapes they show and hide (they are not parts of the rig's tree).
std::set<int> swaps_and_triggers(const Character& ch, Rig& rig);

/// A [[physics]] chain for each limb or stroke named hair, ear, tail or antenna, hanging from
/// its parent, its handle the chain's end.
void add_named_chains(const Character& ch, AutoRig& out);

}  // namespace mar
