// The reader of the scene's [contact] table and its [[contact.pairs]], and the bodies' field
// groups that bonded pairs make (shared by the scene reader, the model reader and the solver).
#include <algorithm>
#include <numeric>
#include <sstream>

#include "common/scene/reader.hpp"

namespace talus {

namespace {

std::string quoted(const std::string& name) { return "'" + scene_reader::echoed(name) + "'"; }

std::string group_names(const std::vector<std::string>& names, const std::vector<int32_t>& of_body, int32_t group) {
  std::string text;
  for (std::size_t b = 0; b < names.size(); ++b)
    if (of_body[b] == group) text += (text.empty() ? "" : " + ") + scene_reader::echoed(names[b]);
  return text;
}

}  // namespace

ContactGroups contact_groups(const ContactSettings& contact, const std::vector<std::string>& names,
                             const std::vector<uint8_t>& fixed) {
  ContactGroups groups;
  const std::size_t n = names.size();
  auto index = [&](const std::string& name) {
    for (std::size_t b = 0; b < n; ++b)
      if (names[b] == name) return static_cast<int32_t>(b);
    return int32_t{-1};
  };
  // Union-find over the bonded pairs.
  std::vector<int32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int32_t b) {
    while (parent[b] != b) b = parent[b] = parent[parent[b]];
    return b;
  };
  const auto& pairs = contact.pairs;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const ContactPair& pair = pairs[i];
    const std::string item = "pair " + std::to_string(i) + " (" + quoted(pair.body_a) + ", " + quoted(pair.body_b) + ")";
    const int32_t a = index(pair.body_a), b = index(pair.body_b);
    // The scene reader refuses such friction pairs; in a model file they never matched a body
    // pair and are left alone, as before bonded pairs.
    if (!pair.bonded && (a < 0 || b < 0 || a == b)) continue;
    if (a < 0 || b < 0) {
      groups.problem = item + ": no body named " + quoted(a < 0 ? pair.body_a : pair.body_b);
      return groups;
    }
    if (a == b) {
      groups.problem = item + ": expected two different bodies";
      return groups;
    }
    for (std::size_t j = 0; j < i; ++j)
      if (std::minmax(index(pairs[j].body_a), index(pairs[j].body_b)) == std::minmax(a, b) && (pair.bonded || pairs[j].bonded)) {
        groups.problem = item + ": the pair is listed twice (also pair " + std::to_string(j) + ")";
        return groups;
      }
    if (pair.bonded) parent[root(a)] = root(b);
  }
  // Groups in the order of their first body.
  std::vector<int32_t> id(n, -1);
  groups.of_body.assign(n, -1);
  for (std::size_t b = 0; b < n; ++b) {
    const int32_t r = root(static_cast<int32_t>(b));
    if (id[r] < 0) {
      id[r] = static_cast<int32_t>(groups.fixed.size());
      groups.fixed.push_back(fixed[b]);  // (with contact off a mixed group is never used)
    } else if (contact.enabled && groups.fixed[id[r]] != fixed[b]) {
      groups.problem = "bonded bodies " + group_names(names, groups.of_body, id[r]) + " + " + scene_reader::echoed(names[b]) +
                       " mix fixed and moving bodies; a fixed body cannot share a velocity field with a moving one "
                       "(hold the moving body with a fixed [boundaries] curve, or leave the pair unbonded)";
      return groups;
    }
    groups.of_body[b] = id[r];
  }
  // One coefficient between two groups: every pair of their bodies must agree.
  const std::size_t count = groups.count();
  groups.friction.assign(count, std::vector<double>(count, contact.friction));
  std::vector<std::vector<std::pair<int32_t, int32_t>>> first(count, std::vector<std::pair<int32_t, int32_t>>(count, {-1, -1}));
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t c = 0; c < n; ++c) {
      const int32_t g = groups.of_body[a], h = groups.of_body[c];
      if (g == h) continue;
      const double mu = pair_friction(contact, names[a], names[c]);
      auto& seen = first[g][h];
      if (seen.first < 0) {
        seen = {static_cast<int32_t>(a), static_cast<int32_t>(c)};
        groups.friction[g][h] = mu;
      } else if (contact.enabled && mu != groups.friction[g][h]) {
        std::ostringstream text;
        text << "bonded bodies share one velocity field, so the pairs between the groups "
             << group_names(names, groups.of_body, g) << " and " << group_names(names, groups.of_body, h)
             << " need one friction coefficient: " << quoted(names[seen.first]) << "-" << quoted(names[seen.second])
             << " has " << groups.friction[g][h] << ", " << quoted(names[a]) << "-" << quoted(names[c]) << " has " << mu
             << " (list each pair with the same friction)";
        groups.problem = text.str();
        return groups;
      }
    }
  return groups;
}

}  // namespace talus

namespace talus::scene_reader {

void read_contact(TableReader& top, Scene& scene) {
  TableReader contact = top.child(top.table("contact"), "contact");
  scene.contact.enabled = contact.boolean("enabled", true);
  scene.contact.friction = contact.number("friction", 0.0, 0, kInf);
  const std::string expected = "expected an array of tables [[contact.pairs]]";
  if (const toml::array* pairs = contact.array("pairs", expected)) {
    for (std::size_t i = 0; i < pairs->size(); ++i) {
      const toml::table* table = (*pairs)[i].as_table();
      if (!table) contact.fail("pairs", expected);
      TableReader r = contact.child(table, "contact.pairs[" + std::to_string(i) + "]");
      ContactPair pair;
      const std::vector<std::string> names = r.strings("bodies");
      if (names.size() != 2 || names[0] == names[1]) r.fail("bodies", "expected two different body names");
      for (const auto& n : names)
        if (scene.body_index(n) < 0) r.fail("bodies", "no body named '" + echoed(n) + "' in [bodies]");
      pair.body_a = names[0];
      pair.body_b = names[1];
      for (std::size_t j = 0; j < scene.contact.pairs.size(); ++j) {
        const ContactPair& other = scene.contact.pairs[j];
        if ((other.body_a == pair.body_a && other.body_b == pair.body_b) ||
            (other.body_a == pair.body_b && other.body_b == pair.body_a))
          r.fail("bodies", "the pair '" + echoed(pair.body_a) + "', '" + echoed(pair.body_b) +
                               "' is listed twice (also contact.pairs[" + std::to_string(j) + "])");
      }
      pair.bonded = r.boolean("bonded", false);
      if (pair.bonded && r.has("friction"))
        r.fail("friction", "a bonded pair takes no friction (its bodies share one velocity field): remove "
                           "friction or bonded");
      if (!pair.bonded) pair.friction = r.number("friction", std::nullopt, 0, kInf);
      r.finish();
      scene.contact.pairs.push_back(pair);
    }
  }
  contact.finish();
  std::vector<std::string> names;
  std::vector<uint8_t> fixed;
  for (const auto& body : scene.bodies) names.push_back(body.name), fixed.push_back(body.fixed);
  if (const std::string problem = contact_groups(scene.contact, names, fixed).problem; !problem.empty())
    contact.fail("pairs", problem);
}

}  // namespace talus::scene_reader
