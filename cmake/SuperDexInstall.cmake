# Installation and the find_package(SuperDex) package config.
# (Filled in by the install work: headers, library, export set, config.)
