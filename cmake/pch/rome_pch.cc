// The translation unit that compiles cmake/RomePch.cmake's precompiled headers (no code of its own).
