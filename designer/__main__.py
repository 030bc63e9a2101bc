from designer.cli.main import entry

entry()
