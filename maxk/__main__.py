from maxk.cli import main

raise SystemExit(main())
