"""Controllers as the doors see them: a personality and its language behind one contract."""
