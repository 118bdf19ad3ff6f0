"""pomkit's applications, built on the library: `python -m pomkit demo | bench | tables`.

They need the `bench` extra's plotting packages; the library (`import pomkit`) does not."""
