// The ini keys of an options struct, each declared once: its name, the member
// it sets, its unit, a one-line description and its check. Loading, saving,
// validation and the documentation of the keys (ini/default.ini's comments)
// all come from the one declaration, so they cannot disagree.
//
//   io::IniKeys<TViewerOptions> keys;
//   keys.number("gui_fps", &TViewerOptions::fps, "Hz", "most redraws a second",
//       {[](double v) { return v > 0 && v <= 60; }, "out of range (0, 60]"});
//   keys.load(options, ini, "pipeline");  // reads, then validates
#pragma once

#include <mrpt/config/CConfigFileBase.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "avm/io/ErrorMessage.h"
#include "avm/io/IniKeyOptions.h"
#include "avm/io/IniOptions.h"

namespace avm::io
{
/** A value as an ini file holds it: true/false, integers as integers, real
 *  numbers as the shortest text that reads back to the same value. */
std::string iniText(bool value);
std::string iniText(std::int64_t value);
std::string iniText(std::uint64_t value);
std::string iniText(double value);
inline std::string iniText(int value) { return iniText(static_cast<std::int64_t>(value)); }
inline std::string iniText(unsigned value) { return iniText(static_cast<std::uint64_t>(value)); }
inline std::string iniText(const std::string& value) { return value; }

/** A check of one value: `ok` false gives the error "[section] key = value: why". */
template <class T>
struct IniRule
{
	std::function<bool(const T&)> ok;
	std::string why;
};

/** What a key's documentation says: the comment of `key = value` lines. */
struct IniKeyDoc
{
	std::string key, unit, description, defaultText;
	/** "description [unit] (default X)", the comment after `key = value //`. */
	std::string comment() const;
};

/** The ini text of a section documenting `keys`: one line each,
 *  "key = default  // description [unit] (default X)". */
std::string documentIniSection(const std::string& section, const std::vector<IniKeyDoc>& keys);

template <class Options>
class IniKeys
{
   public:
	/** A number or bool. It is parsed as `ReadAs` (default: the member's
	 *  type; e.g. int for an unsigned member so that -1 gets the rule's
	 *  message, not a parse error), checked by `rule`, then stored. */
	template <class ReadAs = void, class T>
	IniKeys& number(std::string key, T Options::*member, std::string unit, std::string description,
		IniRule<std::conditional_t<std::is_void_v<ReadAs>, T, ReadAs>> rule = {})
	{
		return addNumber<ReadAs, T>(
			std::move(key), [member](auto& o) -> auto& { return o.*member; }, std::move(unit), std::move(description),
			std::move(rule));
	}

	/** The same for a member of a member (`o.*outer.*inner`). */
	template <class ReadAs = void, class Outer, class T>
	IniKeys& number(std::string key, Outer Options::*outer, T Outer::*inner, std::string unit, std::string description,
		IniRule<std::conditional_t<std::is_void_v<ReadAs>, T, ReadAs>> rule = {})
	{
		return addNumber<ReadAs, T>(
			std::move(key), [=](auto& o) -> auto& { return o.*outer.*inner; }, std::move(unit), std::move(description),
			std::move(rule));
	}

	/** Text, stored after `normalise` (if given) and checked by `rule`. */
	IniKeys& text(std::string key, std::string Options::*member, std::string description,
		IniRule<std::string> rule = {}, std::function<std::string(const std::string&)> normalise = {})
	{
		Key k{std::move(key), "", std::move(description), {}, {}};
		k.parse = [member, normalise](Options& o, const std::string& value, const std::string&)
		{ o.*member = normalise ? normalise(value) : value; };
		k.format = [member](const Options& o) { return o.*member; };
		m_keys.push_back(std::move(k));
		if (rule.ok)
			addRule(
				m_keys.back().name, [member, ok = std::move(rule.ok)](const Options& o) { return ok(o.*member); },
				rule.why);
		return *this;
	}

	/** One of an enum's values by name: `parse` throws std::invalid_argument
	 *  on an unknown name, reported with `why` (empty: the parser's message). */
	template <class Enum, class Parse, class Format>
	IniKeys& choice(std::string key, Enum Options::*member, Parse parse, Format format, std::string description,
		std::string why = {})
	{
		Key k{std::move(key), "", std::move(description), {}, {}};
		k.parse = [member, parse, why, name = k.name](Options& o, const std::string& value, const std::string& section)
		{
			try
			{
				o.*member = parse(value);
			}
			catch (const std::invalid_argument& e)
			{
				throw iniValueError(section, name, value, why.empty() ? std::string(e.what()) : why);
			}
		};
		k.format = [member, format](const Options& o) { return format(o.*member); };
		m_keys.push_back(std::move(k));
		return *this;
	}

	/** The keys of `inner` (declared for the type of `member`) as keys of Options. */
	template <class Inner>
	IniKeys& include(Inner Options::*member, const IniKeys<Inner>& inner)
	{
		for (const auto& k : inner.m_keys)
			m_keys.push_back({k.name, k.unit, k.description,
				[member, parse = k.parse](Options& o, const std::string& v, const std::string& s)
				{ parse(o.*member, v, s); },
				[member, format = k.format](const Options& o) { return format(o.*member); }});
		for (const auto& c : inner.m_checks)
			m_checks.push_back({c.key, [member, ok = c.ok](const Options& o) { return ok(o.*member); },
				[member, why = c.why](const Options& o) { return why(o.*member); }});
		for (const auto& r : inner.m_renamed) m_renamed.push_back({r.oldKey, r.key});
		return *this;
	}

	/** `oldKey`, an earlier name of `key`: still read, as `key` when `key`
	 *  is absent, with a warning that names both (warnRenamedKey); never
	 *  written, so that a saved file has the new name. */
	IniKeys& renamed(std::string oldKey, std::string key)
	{
		m_renamed.push_back({std::move(oldKey), std::move(key)});
		return *this;
	}

	/** The earlier names that renamed() declared. */
	std::vector<std::string> oldKeyNames() const
	{
		std::vector<std::string> names;
		for (const auto& r : m_renamed) names.push_back(r.oldKey);
		return names;
	}

	/** A check across keys, reported on `key` (e.g. max_depth > min_depth). */
	IniKeys& check(const std::string& key, std::function<bool(const Options&)> ok, std::string why)
	{
		return addRule(key, std::move(ok), std::move(why));
	}
	/** The same with a message that shows other values. */
	IniKeys& check(
		const std::string& key, std::function<bool(const Options&)> ok, std::function<std::string(const Options&)> why)
	{
		m_checks.push_back({key, std::move(ok), std::move(why)});
		return *this;
	}

	/** Reads every key present in [section] (absent keys keep their value),
	 *  then validates. Throws std::invalid_argument "[section] key = value: why". */
	void load(Options& o, const mrpt::config::CConfigFileBase& ini, const std::string& section) const
	{
		for (const auto& k : m_keys)
			if (const auto value = readKeyText(ini, section, k.name)) k.parse(o, *value, section);
		validate(o, section);
	}

	/** Writes every key, as load reads it back. */
	void save(const Options& o, mrpt::config::CConfigFileBase& ini, const std::string& section) const
	{
		for (const auto& k : m_keys) ini.write(section, k.name, k.format(o));
	}

	/** Throws std::invalid_argument "[section] key = value: why" for the first failed check. */
	void validate(const Options& o, const std::string& section) const
	{
		for (const auto& c : m_checks)
			if (!c.ok(o)) throw iniValueError(section, c.key, valueText(o, c.key), c.why(o));
	}

	/** Every key's documentation, with `defaults`' values. */
	std::vector<IniKeyDoc> documentation(const Options& defaults) const
	{
		std::vector<IniKeyDoc> docs;
		for (const auto& k : m_keys) docs.push_back({k.name, k.unit, k.description, k.format(defaults)});
		return docs;
	}

   private:
	template <class>
	friend class IniKeys;

	struct Key
	{
		std::string name, unit, description;
		std::function<void(Options&, const std::string& value, const std::string& section)> parse;
		std::function<std::string(const Options&)> format;
	};
	struct Check
	{
		std::string key;
		std::function<bool(const Options&)> ok;
		std::function<std::string(const Options&)> why;
	};
	struct Renamed
	{
		std::string oldKey, key;
	};

	/** The text of [section] key, else of an old name of it (warned about). */
	std::optional<std::string> readKeyText(
		const mrpt::config::CConfigFileBase& ini, const std::string& section, const std::string& key) const
	{
		auto value = readIniText(ini, section, key);
		for (const auto& r : m_renamed)
			if (r.key == key)
				if (const auto old = readIniText(ini, section, r.oldKey))
				{
					warnRenamedKey(section, r.oldKey, key, value.has_value());
					if (!value) value = old;
				}
		return value;
	}

	template <class ReadAs, class T, class Access>
	IniKeys& addNumber(std::string key, Access access, std::string unit, std::string description,
		IniRule<std::conditional_t<std::is_void_v<ReadAs>, T, ReadAs>> rule)
	{
		using Read = std::conditional_t<std::is_void_v<ReadAs>, T, ReadAs>;
		Key k{std::move(key), std::move(unit), std::move(description), {}, {}};
		// A value is checked as read (a negative count is "must be >= 0"), and stored only if it passes.
		k.parse = [access, ok = rule.ok, why = rule.why, name = k.name](
					  Options& o, const std::string& value, const std::string& section)
		{
			const Read v = parseIniValue<Read>(section, name, value);
			if (ok && !ok(v)) throw iniValueError(section, name, iniText(v), why);
			access(o) = static_cast<T>(v);
		};
		k.format = [access](const Options& o) { return iniText(static_cast<Read>(access(o))); };
		m_keys.push_back(std::move(k));
		if (rule.ok)
			addRule(
				m_keys.back().name,
				[access, ok = std::move(rule.ok)](const Options& o) { return ok(static_cast<Read>(access(o))); },
				std::move(rule.why));
		return *this;
	}

	IniKeys& addRule(const std::string& key, std::function<bool(const Options&)> ok, std::string why)
	{
		m_checks.push_back({key, std::move(ok), [why = std::move(why)](const Options&) { return why; }});
		return *this;
	}

	std::string valueText(const Options& o, const std::string& key) const
	{
		for (const auto& k : m_keys)
			if (k.name == key) return k.format(o);
		return {};
	}

	std::vector<Key> m_keys;
	std::vector<Check> m_checks;
	std::vector<Renamed> m_renamed;
};

template <class Options>
void CIniKeyOptions<Options>::loadFromConfigFile(
	const mrpt::config::CConfigFileBase& source, const std::string& section)
{
	auto& self = static_cast<Options&>(*this);
	self.iniKeys().load(self, source, section);
}

template <class Options>
void CIniKeyOptions<Options>::saveToConfigFile(mrpt::config::CConfigFileBase& target, const std::string& section) const
{
	const auto& self = static_cast<const Options&>(*this);
	self.iniKeys().save(self, target, section);
}

template <class Options>
void CIniKeyOptions<Options>::validate(const std::string& section) const
{
	const auto& self = static_cast<const Options&>(*this);
	self.iniKeys().validate(self, section);
}

template <class Options>
std::vector<std::string> CIniKeyOptions<Options>::oldKeyNames() const
{
	return static_cast<const Options&>(*this).iniKeys().oldKeyNames();
}
}  // namespace avm::io
