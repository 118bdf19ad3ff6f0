"""pomkit's applications, built on the library: `python -m pomkit demo | bench`.

They need the `bench` extra's plotting packages (the demo also the `demo` extra's); the library
(`import pomkit`) does not. What measures the project itself (goals, tables) is tools/, outside
the package."""
