// The names of an enum's values, declared once: the text ini files, logs and
// stats.json use for each value, and the way back, whose error lists the
// alternatives (so every option that is a choice reads and fails alike).
//
//   const io::EnumNames<Mode> kModeNames("mode", {{Mode::Fast, "fast"}, {Mode::Exact, "exact"}});
//   kModeNames.name(Mode::Fast);  // "fast"
//   kModeNames.parse("exakt");    // throws "unknown mode 'exakt' (expected fast or exact)"
#pragma once

#include <initializer_list>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace avm::io
{
template <class Enum>
class EnumNames
{
   public:
	/** `what` names the idea in errors ("switch policy"). */
	EnumNames(std::string what, std::initializer_list<std::pair<Enum, const char*>> names)
		: m_what(std::move(what)), m_names(names)
	{
	}

	std::string name(Enum value) const
	{
		for (const auto& [v, n] : m_names)
			if (v == value) return n;
		throw std::logic_error("EnumNames: a " + m_what + " without a name");
	}

	/** The value named `text`; std::invalid_argument
	 *  "unknown <what> '<text>' (expected a, b or c)" otherwise. */
	Enum parse(const std::string& text) const
	{
		for (const auto& [v, n] : m_names)
			if (text == n) return v;
		throw std::invalid_argument("unknown " + m_what + " '" + text + "' (expected " + alternatives() + ")");
	}

	/** "a, b or c". */
	std::string alternatives() const
	{
		std::string s;
		for (std::size_t i = 0; i < m_names.size(); i++)
			s += (i == 0 ? "" : i + 1 == m_names.size() ? " or " : ", ") + std::string(m_names[i].second);
		return s;
	}

   private:
	std::string m_what;
	std::vector<std::pair<Enum, const char*>> m_names;
};
}  // namespace avm::io
