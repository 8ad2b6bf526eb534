// The reader of the scene's [contact] table and its [[contact.pairs]].
#include "common/scene_reader.hpp"

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
      pair.friction = r.number("friction", std::nullopt, 0, kInf);
      r.finish();
      scene.contact.pairs.push_back(pair);
    }
  }
  contact.finish();
}

}  // namespace talus::scene_reader
