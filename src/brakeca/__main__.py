from brakeca.cli import main

main()
