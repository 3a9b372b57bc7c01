#pragma once
// Options in the unit tests, set through their INI keys as a user sets them (a value out of range or not one of a
// mode's names is the loader's InputError).
#include <mrpt/config/CConfigFileMemory.h>

#include <string>

namespace quasiloc::frontend::test
{
/** `options` with the lines `text` ("key = value\n...") of INI section `section` loaded over them. */
template <class Options>
Options withIni(Options options, const std::string& section, const std::string& text)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.setContent("[" + section + "]\n" + text + "\n");
    options.loadFromConfigFile(cfg, section);
    return options;
}
}  // namespace quasiloc::frontend::test
